"""Damaged archives, outputs that would destroy data, and options no analysis can use: one
message naming the file or option and what is allowed, exit 2, no traceback, inputs unchanged.
Each case ended in a traceback, exited 0 with wrong numbers, or overwrote its input before."""
import hashlib
import os

import h5py
import numpy as np
import pytest

from test_scripts import PYTHON, TOOLS, run

ANALYZE = os.path.join(TOOLS, "jamsim_analyze.py")
REPORT = os.path.join(TOOLS, "jamsim_report.py")
PLOT_REPLICA = os.path.join(TOOLS, "plot_replica.py")


def refused(out, *words):
    assert out.returncode == 2, (out.stdout, out.stderr)
    assert "Traceback" not in out.stderr, out.stderr
    for w in words:
        assert w in out.stderr, (w, out.stderr)


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def _delete(name):
    def edit(f):
        del f[name]
    return edit


def _replace(name, value):
    def edit(f):
        del f[name]
        f[name] = value
    return edit


def _set(name, row, value):
    def edit(f):
        f[name][row] = value
    return edit


def _attr(name, value):
    def edit(f):
        f.attrs[name] = value
    return edit


# (what the edit does, the edit, words of the refusal)
CAMPAIGN_DAMAGE = {
    "status_missing": (_delete("replicas/status"), "/replicas/status is missing"),
    "n_samples_missing": (_delete("replicas/n_samples"), "/replicas/n_samples is missing"),
    "N_missing": (_delete("replicas/N"), "/replicas/N is missing"),
    "phi_short": (lambda f: _replace("replicas/phi", f["replicas/phi"][:1])(f),
                  "/replicas/phi has shape (1,)"),
    "status_2d": (lambda f: _replace("replicas/status", f["replicas/status"][...][:, None])(f),
                  "/replicas/status has shape"),
    "status_unknown": (_set("replicas/status", 0, 7), "/replicas/status holds 7"),
    "timeseries_rows": (lambda f: _replace("timeseries/pressure", f["timeseries/pressure"][:1])(f),
                        "/timeseries/pressure has shape (1,"),
    "timeseries_text": (lambda f: _replace("timeseries/pressure", np.full(f["timeseries/pressure"].shape, b"x"))(f),
                        "/timeseries/pressure has shape"),
    "n_samples_negative": (_set("replicas/n_samples", 0, -5), "/replicas/n_samples[0] = -5 for a done replica"),
    "n_samples_beyond": (_set("replicas/n_samples", 0, 1e9), "/replicas/n_samples[0] = 1e+09 for a done replica"),
    "layout_newer": (_attr("layout_version", 99), "has archive layout 99; this package reads layouts up to"),
    "strain_missing": (_delete("timeseries/strain"), "/timeseries/strain is missing"),
    "model_missing": (lambda f: f.attrs.__delitem__("model"), "the root attribute model is missing"),
    "N_nan": (_set("replicas/N", 0, np.nan), "replica 0 is done with N = nan"),
    "phi_zero": (_set("replicas/phi", 0, 0.0), "replica 0 is done with N = 64, phi = 0"),
    "rate_negative": (_set("replicas/rate", 0, -1e-3), "replica 0 is done with rate = -0.001 (rate >= 0)"),
    "transient_missing": (_delete("replicas/transient"), "/replicas/transient is missing"),
    "progress_high": (_set("replicas/progress", 0, 5.0),
                      "/replicas/progress[0] is 5 (the fraction of its steps done, from 0 to 1)"),
    "progress_nan": (_set("replicas/progress", 0, np.nan), "/replicas/progress[0] is nan"),
    "rank_negative": (_set("replicas/rank", 0, -3), "/replicas/rank[0] is -3 (the MPI rank that ran it"),
    "evaluations_negative": (_set("replicas/force_evaluations", 0, -1),
                             "/replicas/force_evaluations[0] is -1 (a whole count from 0)"),
    "wall_negative": (_set("replicas/wall_seconds", 0, -2.0), "/replicas/wall_seconds[0] is -2"),
    "status_float": (lambda f: _replace("replicas/status", f["replicas/status"][...].astype("f8"))(f),
                     "/replicas/status holds float64, not integers"),
}


@pytest.mark.parametrize("case", sorted(CAMPAIGN_DAMAGE))
def test_damaged_campaign_archive_is_refused(case, small_archive, copy_of):
    edit, words = CAMPAIGN_DAMAGE[case]
    path = copy_of(small_archive, f"{case}.h5")
    with h5py.File(path, "r+") as f:
        edit(f)
    before = digest(path)
    refused(run(ANALYZE, "summary", path), f"'{path}'", words)
    assert digest(path) == before


@pytest.mark.parametrize("case", ["identity", "N_text", "phi_missing", "strain_missing", "rate_negative",
                                  "transient_missing"])
def test_damaged_replica_file_is_refused(case, jamsim, tmp_path):
    path = str(tmp_path / "r.h5")
    made = run(jamsim, "replica", "--N", "16", "--phi", "0.8", "--rate", "1e-2", "--strain", "0.05", "-o", path)
    assert made.returncode == 0, made.stderr
    with h5py.File(path, "r+") as f:
        if case == "identity":
            f.attrs["identity"] = "zzz-not-hex"
        elif case == "N_text":
            f.attrs["N"] = "abc"
        elif case == "phi_missing":
            del f.attrs["phi"]
        elif case == "rate_negative":
            f.attrs["rate"] = -0.01
        elif case == "transient_missing":
            del f.attrs["transient"]
        else:
            del f["timeseries/strain"]
    words = {"identity": "identity = 'zzz-not-hex' is not hexadecimal", "N_text": "N = 'abc' is not a number",
             "phi_missing": "the root attribute phi is missing", "strain_missing": "/timeseries/strain is missing",
             "rate_negative": "the root attribute rate = -0.01 is below 0",
             "transient_missing": "the root attribute transient is missing"}
    refused(run(ANALYZE, "summary", path), words[case])


def test_an_archive_is_never_an_output(small_archive, copy_of, tmp_path):
    path = copy_of(small_archive, "same.h5")
    before = digest(path)
    refused(run(ANALYZE, "averages", path, "--output", path), f"--output '{path}' is an input")
    other = copy_of(small_archive, "other.h5")
    refused(run(ANALYZE, "averages", path, "--output", other), "is an HDF5 file (an archive?)")
    refused(run(PLOT_REPLICA, path, str(tmp_path / "figure.txt"), "--replica", "0"), "a file name ending in .png")
    refused(run(ANALYZE, "picture", path, "--output", other), "a file name ending in .png")
    assert digest(path) == before and digest(other) == digest(small_archive)


def test_report_outdir_under_a_file(small_archive, tmp_path):
    (tmp_path / "a_file").write_text("x")
    refused(run(REPORT, small_archive, str(tmp_path / "a_file" / "sub")), "cannot create OUTDIR", "Not a directory")


@pytest.mark.parametrize("args,words", [
    (["--degree", "0"], "--degree = 0 is not allowed"),
    (["--bootstrap", "1"], "--bootstrap = 1 is not allowed: 0 (none) or from 10 to 100000"),
    (["--start", "0.84", "0.28", "0"], "--start = 0.84 0.28 0 is not allowed"),
    (["--phi-min", "0.9", "--phi-max", "0.8"], "--phi-min = 0.9 is not allowed: below --phi-max"),
    (["--rate-max", "-1"], "--rate-max = -1.0 is not allowed"),
    (["--phi-min", "nan"], "--phi-min = nan is not allowed"),
    (["--phi-min", "-5"], "--phi-min = -5.0 is not allowed: a packing fraction, 0 < phi < 1"),
    (["--phi-max", "2"], "--phi-max = 2.0 is not allowed: a packing fraction, 0 < phi < 1"),
])
def test_collapse_options_no_fit_can_use(args, words, small_archive, tmp_path):
    refused(run(ANALYZE, "collapse", small_archive, str(tmp_path / "c"), *args), words)
    if args[0] != "--start":  # the report takes every collapse option but the start values
        refused(run(REPORT, small_archive, str(tmp_path / "r"), *args), words)


def test_test_level_and_plateau_level(small_archive, tmp_path):
    refused(run(ANALYZE, "compare", small_archive, small_archive, "--by", "file", "--alpha", "5"),
            "--alpha = 5.0 is not allowed")
    refused(run(ANALYZE, "newtonian", small_archive, str(tmp_path / "n"), "--plateau-p", "-1"),
            "--plateau-p = -1.0 is not allowed")
    refused(run(REPORT, small_archive, str(tmp_path / "r"), "--N", "0"), "--N = 0 is not allowed")


def test_transient_length_settled_from_within_the_runs(small_archive):
    tool = os.path.join(TOOLS, "transient_length.py")
    refused(run(tool, small_archive, "--settled-from", "nan"), "--settled-from = nan is not allowed")
    refused(run(tool, small_archive, "--settled-from", "-1"), "--settled-from = -1.0 is not allowed")
    refused(run(tool, small_archive, "--settled-from", "1e6"), "--settled-from = 1e+06 is not allowed",
            "at least 2 samples must follow it")


def test_final_cell_without_a_side(small_archive, copy_of, tmp_path):
    path = copy_of(small_archive, "side.h5")
    with h5py.File(path, "r+") as f:
        f["final/box_side"][0] = np.nan
    refused(run(ANALYZE, "picture", path, "--output", str(tmp_path / "p.png")),
            "the final cell of replica row 0 has side nan")


def test_model_not_in_the_archives(small_archive, tmp_path):
    refused(run(ANALYZE, "collapse", small_archive, str(tmp_path / "c"), "--model", "XX"),
            "--model XX is not in", "(models: RD0)")


def _all_replicas(f, name, edit):
    """Apply edit(row array) -> row array to every done replica's /timeseries/name."""
    data = f[f"timeseries/{name}"][...]
    for r, n in enumerate(f["replicas/n_samples"][...]):
        data[r, :int(n)] = edit(data[r, :int(n)].copy())
    f[f"timeseries/{name}"][...] = data


def test_strain_that_decreases_is_refused(small_archive, copy_of):
    path = copy_of(small_archive, "back.h5")
    with h5py.File(path, "r+") as f:
        f["timeseries/strain"][0, 3] = -1.0
    refused(run(ANALYZE, "averages", path, "--observable", "pressure"), f"'{path}' is damaged",
            "replica 0's strain decreases at sample 3")


def test_negative_pressure_is_left_out_and_all_negative_refused(small_archive, copy_of):
    path = copy_of(small_archive, "negative.h5")
    with h5py.File(path, "r+") as f:
        f["timeseries/pressure"][0, 5] = -1e-3
    out = run(ANALYZE, "averages", path, "--observable", "pressure")
    assert out.returncode == 0, out.stderr
    assert "pressure < 0 at sample 5 (-0.001), which jamsim never writes" in out.stdout, out.stdout
    with h5py.File(path, "r+") as f:
        _all_replicas(f, "pressure", lambda v: -np.abs(v) - 1e-9)
    refused(run(ANALYZE, "averages", path, "--observable", "pressure"), "no finished replica left to average")
    refused(run(REPORT, path, os.path.join(os.path.dirname(path), "report")), "every replica was left out",
            "pressure < 0 at sample 0")


def test_infinite_sample_is_left_out_without_numpy_warnings(small_archive, copy_of):
    path = copy_of(small_archive, "inf.h5")
    with h5py.File(path, "r+") as f:
        f["timeseries/pressure"][0, int(f["replicas/n_samples"][0]) - 1] = np.inf
    out = run(ANALYZE, "averages", path, "--observable", "pressure")
    assert out.returncode == 0, out.stderr
    assert "pressure not finite after the transient" in out.stdout, out.stdout
    assert "RuntimeWarning" not in out.stderr, out.stderr


def test_averages_output_writes_counts_as_integers(small_archive, tmp_path):
    target = tmp_path / "means.tsv"
    out = run(ANALYZE, "averages", small_archive, "--observable", "pressure", "--output", str(target))
    assert out.returncode == 0, out.stderr
    header, first = target.read_text().splitlines()[:2]
    row = dict(zip(header.split("\t"), first.split("\t")))
    assert row["N"] == "64" and row["seeds"].isdigit(), row


def test_a_file_on_which_hdf5_loops_is_refused_after_the_deadline(small_archive, copy_of, monkeypatch):
    """The objects of the first global heap zeroed (as a crash can leave them): HDF5 1.10
    loops for ever reading the attributes; the tools gave up only when killed."""
    path = copy_of(small_archive, "heap_zeroed.h5")
    with open(path, "r+b") as f:
        data = f.read()
        at = data.index(b"GCOL")
        size = int.from_bytes(data[at + 8:at + 16], "little")
        f.seek(at + 16)
        f.write(bytes(size - 16))
    before = digest(path)
    monkeypatch.setenv("JAMSIM_READ_DEADLINE_SECONDS", "2")
    for tool in ((ANALYZE, "summary"), (ANALYZE, "averages"), (PLOT_REPLICA,)):
        refused(run(*tool, path, *(["out.png"] if tool[0] == PLOT_REPLICA else [])),
                f"reading '{path}' did not finish within 2 s: its HDF5 structure is damaged")
    assert digest(path) == before


@pytest.mark.parametrize("edit, words", [
    (lambda f: f.attrs.__setitem__("layout_version", np.array([4, 4])), "its attribute layout_version is not one integer"),
    (lambda f: f.attrs.__setitem__("campaign", np.int64(5)), "its attribute campaign is not text"),
    (lambda f: f.attrs.__setitem__("model", np.int64(3)), "its attribute model is not text"),
    (lambda f: f.attrs.__setitem__("spec_text", np.bytes_(b"\xff\xfe")), "its attribute spec_text is not UTF-8 text"),
    (lambda f: f["replicas"].__delitem__("seed"), "/replicas/seed is missing"),
])
def test_edited_root_attributes_are_refused(small_archive, copy_of, edit, words):
    """Each ended in a TypeError, UnicodeDecodeError or KeyError traceback (plot_campaign too)."""
    path = copy_of(small_archive, "edited.h5")
    with h5py.File(path, "r+") as f:
        edit(f)
    before = digest(path)
    refused(run(ANALYZE, "summary", path), f"'{path}' is damaged: {words}")
    refused(run(os.path.join(TOOLS, "plot_campaign.py"), path, os.path.join(os.path.dirname(path), "plots")),
            f"'{path}' is damaged: {words}")
    assert digest(path) == before


@pytest.mark.parametrize("value", ["abc", "5s", "0", "0.5", "-5", "1e9", "inf", "nan", " 7"])
def test_a_bad_read_deadline_is_refused(small_archive, monkeypatch, value):
    """JAMSIM_READ_DEADLINE_SECONDS that is not a number of seconds stood silently for 60 s."""
    monkeypatch.setenv("JAMSIM_READ_DEADLINE_SECONDS", value)
    refused(run(ANALYZE, "summary", small_archive),
            f'JAMSIM_READ_DEADLINE_SECONDS = "{value}" is not allowed: a number of seconds, at least 1 and below 1e9')


def test_an_output_folder_named_with_spaces_is_refused(small_archive, tmp_path):
    """The report made a folder 'rep ' (a trailing space) without a word."""
    target = str(tmp_path / "rep ")
    refused(run(REPORT, small_archive, target), f"OUTDIR '{target}' is not allowed: a folder name that neither")
    assert not os.path.exists(target)


def test_odd_paths_are_refused(small_archive, tmp_path):
    refused(run(ANALYZE, "summary", ""), "an empty path is not an archive")
    pipe = tmp_path / "pipe.h5"
    os.mkfifo(pipe)
    refused(run(ANALYZE, "summary", str(pipe)), "is not a regular file")
    refused(run(ANALYZE, "averages", small_archive, "--output", ""), "--output '': an empty file name")


def test_outputs_never_overwrite_other_files(small_archive, tmp_path):
    """averages --output wrote its table over any file (a campaign file too); a file kept under
    OUTPUT.tmp was overwritten and removed by csv; an unwritable output ended in a traceback."""
    victim = tmp_path / "campaign.toml"
    victim.write_text("[campaign]\n")
    refused(run(ANALYZE, "averages", small_archive, "--output", str(victim)), "a file name ending in .tsv or .txt")
    assert victim.read_text() == "[campaign]\n"
    kept = tmp_path / "means.csv.tmp"
    kept.write_text("precious")
    mask = os.umask(0o022)
    try:
        out = run(ANALYZE, "csv", small_archive, "-o", str(tmp_path / "means.csv"))
    finally:
        os.umask(mask)
    assert out.returncode == 0, out.stderr
    assert kept.read_text() == "precious" and (tmp_path / "means.csv").exists()
    assert (tmp_path / "means.csv").stat().st_mode & 0o777 == 0o644  # a new file's mode, not mkstemp's 0600
    assert not [p for p in os.listdir(tmp_path) if p.startswith("means.csv.") and p != "means.csv.tmp"]
    refused(run(ANALYZE, "csv", small_archive, "-o", "/proc/means.csv"), "'/proc/means.csv' cannot be written")


def test_report_and_compare_refuse_what_they_cannot_mean(small_archive, copy_of, tmp_path):
    """Each was accepted: a size missing from the data (the report exited 0 with its analyses
    'not run'), an OUTDIR named like an archive (a mistyped archive became a folder), one file
    compared with itself under two names, a bootstrap of 10^9 fits."""
    refused(run(REPORT, small_archive, str(tmp_path / "rep"), "--N", "63"), "--N = 63 is not allowed: no finished "
            "replica has N = 63")
    refused(run(REPORT, small_archive, str(tmp_path / "typo.h5")), "ends in .h5, as an archive does")
    assert not (tmp_path / "typo.h5").exists() and not (tmp_path / "rep").exists()
    same = copy_of(small_archive, "same.h5")
    twice = os.path.join(os.path.dirname(same), ".", "same.h5")
    refused(run(ANALYZE, "compare", same, twice, "--by", "file"), "are the same file")
    refused(run(ANALYZE, "collapse", small_archive, str(tmp_path / "col"), "--bootstrap", "1000000000"),
            "--bootstrap = 1000000000 is not allowed")


def test_an_archive_whose_replicas_all_failed_says_so(small_archive, copy_of, tmp_path):
    """plot_campaign.py said 'no finished replica ... yet' and transient_length.py that CD0 was
    no sheared-flow model; both now say how many failed and the first reason."""
    path = copy_of(small_archive, "all_failed.h5")
    with h5py.File(path, "r+") as f:
        f["replicas/status"][...] = 3
        f["replicas/failure_reason"][0] = b"the reason"
    for tool in ("plot_campaign.py", "transient_length.py"):
        extra = [str(tmp_path / "figures")] if tool == "plot_campaign.py" else []
        refused(run(os.path.join(TOOLS, tool), path, *extra), "no finished replica", " failed (replica 0: the reason)")


def test_a_closed_pipe_is_no_damaged_archive(small_archive):
    """`averages | head -1` said '[Errno 32] Broken pipe (a damaged archive?)'."""
    import subprocess
    out = subprocess.run(f"'{PYTHON}' '{ANALYZE}' averages '{small_archive}' | head -c 1", shell=True,
                         capture_output=True, text=True, timeout=120)
    assert "damaged" not in out.stderr and "Traceback" not in out.stderr, out.stderr


def test_an_empty_collapse_window_names_the_window_and_the_data(small_archive, tmp_path):
    """The refusal named neither the window asked for nor where the data lie."""
    out = run(ANALYZE, "collapse", small_archive, str(tmp_path / "out"), "--phi-min", "0.95", "--phi-max", "0.96")
    refused(out, "in the window 0.95 <= phi <= 0.96, rate <= inf (the data of that N have phi ")
    assert not os.path.exists(tmp_path / "out" / "collapse_pressure.csv")


def test_collapse_refuses_a_file_as_outdir_before_the_fit(small_archive, tmp_path):
    """The whole fit ran and printed its results before the output folder was refused."""
    outdir = tmp_path / "a_file"
    outdir.write_text("x")
    out = run(ANALYZE, "collapse", small_archive, str(outdir))
    refused(out, f"OUTDIR '{outdir}' is an existing file, not a directory")
    assert out.stdout == "", out.stdout


def test_transient_length_refusal_comes_alone(small_archive):
    """The table's header was printed before the refusal."""
    out = run(os.path.join(TOOLS, "transient_length.py"), small_archive, "--settled-from", "50")
    refused(out, "--settled-from = 50 is not allowed")
    assert out.stdout == "", out.stdout


@pytest.mark.parametrize("clock", ["time", "strain"])
def test_averages_of_a_clock_are_refused_in_words(small_archive, clock):
    """It said "no finished replica left to average", which blamed the replicas."""
    refused(run(ANALYZE, "averages", small_archive, "--observable", clock),
            f"--observable {clock} is not allowed: a quantity of the steady state")


def test_report_usage_names_one_outdir():
    out = run(os.path.join(TOOLS, "jamsim_report.py"), "--help")
    assert out.returncode == 0, out.stderr
    assert "ARCHIVE [ARCHIVE ...] OUTDIR" in out.stdout and "OUTDIR [ARCHIVE" not in out.stdout, out.stdout
