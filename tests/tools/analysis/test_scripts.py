"""The scripts a user runs (tools/*.py, tools/*.sh, slurm/*.sh, slurm/*.sbatch): every one
answers --help with a usage on stdout and exit status 0; the analysis scripts read several
archives as one (campaigns of other sweeps, with a replica in two of them counted once) and
give the same answer as the campaign run whole; bad input gets one message naming the file
or argument, exit status 2 and no traceback."""
import glob
import os
import re
import shutil
import subprocess

import h5py
import numpy as np
import pytest

import jamsim_analysis as ja
from conftest import CAMPAIGNS, ROOT, run_campaign

PYTHON = "/usr/bin/python3"
TOOLS = os.path.join(ROOT, "tools")
SCRIPTS = sorted(glob.glob(os.path.join(TOOLS, "*.py")) + glob.glob(os.path.join(TOOLS, "*.sh"))
                 + glob.glob(os.path.join(TOOLS, "bench", "*.sh"))
                 + glob.glob(os.path.join(ROOT, "slurm", "*.sh")) + glob.glob(os.path.join(ROOT, "slurm", "*.sbatch")))


def script(name):
    return os.path.join(TOOLS, name)


def run(*args, cwd=None):
    cmd = [str(a) for a in args]
    if cmd[0].endswith(".py"):
        cmd = [PYTHON] + cmd
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=120,
                          env=dict(os.environ, MPLBACKEND="Agg"))


@pytest.mark.parametrize("path", SCRIPTS, ids=[os.path.relpath(p, ROOT) for p in SCRIPTS])
def test_every_script_answers_help(path, tmp_path):
    """Run from an empty folder with a short time limit: --help must not start the work."""
    cmd = ([PYTHON, path] if path.endswith(".py") else ["bash", path]) + ["--help"]
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path, timeout=60,
                         env=dict(os.environ, SLURM_LOCAL_DIR=str(tmp_path / "slurm")))
    assert out.returncode == 0, (path, out.stdout, out.stderr)
    lines = [line for line in out.stdout.splitlines() if line.strip()]
    assert len(lines) >= 2 and not out.stderr.strip(), (path, out.stdout, out.stderr)
    assert os.listdir(tmp_path) == [], (path, os.listdir(tmp_path))  # nothing done
    assert os.path.basename(path) in out.stdout, out.stdout  # its usage, not some other output
    if path.endswith(".py"):
        assert "usage:" in out.stdout, out.stdout


def test_scripts_are_all_covered():
    names = {os.path.basename(p) for p in SCRIPTS}
    assert {"plot_campaign.py", "plot_replica.py", "analyze_jamming.py", "jamsim_analyze.py", "jamsim_report.py",
            "transient_length.py", "quickstart.sh", "submit_campaign.sh", "merge.sbatch", "bench_farm.sh",
            "cost_accuracy.sh"} <= names


def test_analyze_jamming_help_defines_its_columns():
    text = " ".join(run(script("analyze_jamming.py"), "--help").stdout.split())
    for column in ("configurations", "P_J", "error", "mean_p_jammed", "mean_Z_jammed", "mean_phi_J",
                   "std_phi_J", "isostatic_fraction"):
        assert re.search(rf"\b{column}\b", text), column
    assert "N_c' = 2(N' - 1) + 1" in text and "excess_contacts = 0" in text and "2d = 4" in text


def campaign_variant(tmp_path, base, name, **sweep):
    """tests/data/campaigns/<base>.toml with other [sweep] values and output <name>.h5."""
    text = open(os.path.join(CAMPAIGNS, f"{base}.toml")).read()
    text = re.sub(r'(?m)^output = .*$', f'output = "{name}.h5"', text)
    for key, value in sweep.items():
        text = re.sub(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def run_spec(jamsim, spec, workdir):
    out = subprocess.run([jamsim, "run", str(spec)], cwd=workdir, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return str(workdir / (spec.stem + ".h5"))


@pytest.fixture(scope="module")
def seeds_split(jamsim, tmp_path_factory):
    """merge_seeds_a (seeds 1, 2), merge_seeds_b (3, 2) and merge_seeds_all (1, 2, 3)."""
    work = str(tmp_path_factory.mktemp("seeds"))
    return [run_campaign(jamsim, work, f"merge_seeds_{c}") for c in ("a", "b", "all")]


@pytest.fixture(scope="module")
def compress_split(jamsim, tmp_path_factory):
    """COMPRESS at N = 32: seeds [1, 2], [2, 3] and 3 (all)."""
    work = tmp_path_factory.mktemp("compress")
    return [run_spec(jamsim, campaign_variant(work, "static_compress", name, seeds=seeds), work)
            for name, seeds in (("a", "[1, 2]"), ("b", "[2, 3]"), ("all", "3"))]


@pytest.fixture(scope="module")
def flow_split(jamsim, tmp_path_factory):
    """analysis_flow in two halves of phi, and whole."""
    work = tmp_path_factory.mktemp("flowsplit")
    return [run_spec(jamsim, campaign_variant(work, "analysis_flow", name, phi=phis), work)
            for name, phis in (("low", "[0.80, 0.83]"), ("high", "[0.89, 0.86]"),
                               ("whole", "[0.80, 0.83, 0.86, 0.89]"))]


def test_archives_read_together_count_a_shared_replica_once(seeds_split):
    a, b, whole = seeds_split
    both, alone = ja.open_archives(a, b), ja.open_archives(whole)
    assert len(ja.open_archives(a).replicas) + len(ja.open_archives(b).replicas) == 8
    assert len(both.replicas) == len(alone.replicas) == 6
    key = lambda t: sorted(zip(t["phi"], t["seed"]))  # noqa: E731
    assert key(both.replicas) == key(alone.replicas)
    for r in both.replicas.itertuples():
        (k,) = alone.replicas.index[(alone.replicas["phi"] == r.phi) & (alone.replicas["seed"] == r.seed)]
        assert np.array_equal(both.series(r.replica, "pressure"), alone.series(int(k), "pressure"))


def test_the_same_replica_with_other_settings_is_refused(seeds_split, copy_of):
    a, b, _ = seeds_split
    longer = copy_of(b, "longer.h5")
    with h5py.File(longer, "r+") as h:
        h["replicas/strain"][...] = 0.2
    with pytest.raises(ja.AnalysisError, match=r"same replica .*strain = 0.1 and 0.2"):
        ja.open_archives(a, longer)


def outputs_equal(dir_a, dir_b, names):
    for name in names:
        x, y = (open(os.path.join(d, name)).read().split("\n") for d in (dir_a, dir_b))
        assert len(x) == len(y), name
        for lx, ly in zip(x, y):
            for u, v in zip(lx.split("\t"), ly.split("\t")):
                try:
                    assert np.isclose(float(u), float(v), rtol=1e-12, atol=0, equal_nan=True), (name, lx, ly)
                except ValueError:
                    assert u == v, (name, lx, ly)


def test_transient_length_and_averages_of_two_archives_equal_the_whole(seeds_split):
    a, b, whole = seeds_split
    tool = script("transient_length.py")
    together, alone = run(tool, a, b), run(tool, whole)
    assert together.returncode == 0 and together.stdout == alone.stdout, (together.stdout, alone.stdout)
    assert re.search(r"(?m)^\s+64\s+0\.800\s+3\.0e-03\s+3 ", alone.stdout), alone.stdout  # 3 seeds, not 4
    tool = script("jamsim_analyze.py")
    together, alone = run(tool, "averages", a, b), run(tool, "averages", whole)
    last = lambda out: out.stdout.strip().split("\n\n")[-1]  # noqa: E731  the averages over seeds
    assert together.returncode == 0 and last(together) == last(alone)


def test_plot_campaign_of_two_archives(seeds_split, tmp_path):
    a, b, _ = seeds_split
    out = run(script("plot_campaign.py"), a, b, tmp_path / "figs", "--replica", "5")
    assert out.returncode == 0, out.stderr
    for name in ("flow_curves.png", "stress_vs_rate.png", "replica_5.png"):
        assert os.path.getsize(tmp_path / "figs" / name) > 5000
    bad = run(script("plot_campaign.py"), a, b, tmp_path / "figs", "--replica", "6")
    assert bad.returncode == 2 and "--replica 6 is not a finished replica (allowed: 0-5)" in bad.stderr


def test_analyze_jamming_of_two_archives_equals_the_whole(compress_split, tmp_path):
    a, b, whole = compress_split
    tool = script("analyze_jamming.py")
    together, alone = run(tool, a, b, tmp_path / "ab"), run(tool, whole, tmp_path / "all")
    assert together.returncode == 0 and alone.returncode == 0, together.stderr + alone.stderr
    outputs_equal(tmp_path / "ab", tmp_path / "all", ["phi_j.tsv", "pj_from_phi_j.tsv"])
    assert open(tmp_path / "all" / "phi_j.tsv").read().split("\n")[1].startswith("32\t3\t")


def test_collapse_of_two_archives_equals_the_whole(flow_split, tmp_path):
    low, high, whole = flow_split
    tool = script("jamsim_analyze.py")
    together = run(tool, "collapse", low, high, tmp_path / "two", "--degree", "1")
    alone = run(tool, "collapse", whole, tmp_path / "one", "--degree", "1")
    assert together.returncode == 0 and alone.returncode == 0, together.stderr + alone.stderr
    x, y = ({row[0]: row[1] for row in (line.split("\t") for line in open(tmp_path / d / "collapse_pressure.tsv"))}
            for d in ("two", "one"))
    assert x.keys() == y.keys() and int(float(x["points"])) == 12
    for k in x:
        if k != "parameter":
            assert np.isclose(float(x[k]), float(y[k]), rtol=1e-9), (k, x[k], y[k])


def test_plot_replica_of_a_campaign(seeds_split, jamsim, tmp_path):
    a, b, whole = seeds_split
    tool = script("plot_replica.py")
    out = run(tool, whole, tmp_path / "r.png")
    assert out.returncode == 2 and "holds 6 replicas: choose one with --replica R (0..5" in out.stderr
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
    out = run(tool, a, b, tmp_path / "r.png", "--replica", "4")
    assert out.returncode == 0 and os.path.getsize(tmp_path / "r.png") > 5000, out.stderr
    one = tmp_path / "one.h5"
    subprocess.run([jamsim, "replica", "--model", "RD0", "--N", "64", "--phi", "0.84", "--rate", "1e-2",
                    "--strain", "0.2", "--seed", "3", "-o", str(one)], check=True, capture_output=True)
    out = run(tool, one, tmp_path / "one.png")
    assert out.returncode == 0 and os.path.getsize(tmp_path / "one.png") > 5000, out.stderr


@pytest.fixture(scope="module")
def bad_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    (d / "text.h5").write_text("not hdf5")
    with h5py.File(d / "other.h5", "w") as h:
        h["data"] = np.zeros(3)
    (d / "a_file").write_text("")
    return d


# Each tool with ARCHIVE standing for the bad file; "wrong" is an archive of the wrong kind.
TOOL_ARGS = {
    "plot_campaign.py": ["ARCHIVE", "OUT"],
    "plot_replica.py": ["ARCHIVE", "OUT/r.png", "--replica", "0"],
    "transient_length.py": ["ARCHIVE"],
    "analyze_jamming.py": ["ARCHIVE", "OUT"],
    "jamsim_analyze.py": ["summary", "ARCHIVE"],
    "jamsim_report.py": ["ARCHIVE", "OUT"],
}
WRONG_KIND = {  # (which archive, the message)
    "plot_campaign.py": ("rand", "model RAND has no flow curves"),
    "plot_replica.py": ("rand", None),
    "transient_length.py": ("rand", "no finished replica with rate > 0"),
    "analyze_jamming.py": ("flow", "model 'RD0' is not allowed: RAND, COOL, COMPRESS"),
    "jamsim_analyze.py": ("rand", None),
    "jamsim_report.py": ("rand", None),
}


def test_tool_table_covers_every_python_script():
    assert set(TOOL_ARGS) == {os.path.basename(p) for p in SCRIPTS if p.endswith(".py")}


@pytest.mark.parametrize("tool", sorted(TOOL_ARGS))
def test_bad_input_gets_one_message_exit_2_no_traceback(tool, bad_files, rand_archive, small_archive, tmp_path):
    cases = [(bad_files / "missing.h5", "missing.h5': no such file"),
             (bad_files / "text.h5", "'" + str(bad_files / "text.h5") + "' is not an HDF5 file (no HDF5 signature)"),
             (bad_files / "other.h5", "other.h5' is neither a jamsim campaign archive")]
    kind, message = WRONG_KIND[tool]
    if message:
        cases.append((rand_archive if kind == "rand" else small_archive, message))
    for path, message in cases:
        args = [str(path) if a == "ARCHIVE" else a.replace("OUT", str(tmp_path / "out")) for a in TOOL_ARGS[tool]]
        out = run(script(tool), *args)
        assert out.returncode == 2, (tool, path, out.stdout, out.stderr)
        assert message in out.stderr and "Traceback" not in out.stderr, (tool, out.stderr)
        assert len(out.stderr.strip().splitlines()) == 1 and out.stderr.startswith(f"{tool}: "), out.stderr
    if "OUT" in TOOL_ARGS[tool]:  # the output directory given as an existing file
        args = [str(small_archive if tool != "analyze_jamming.py" else rand_archive) if a == "ARCHIVE"
                else str(bad_files / "a_file") if a == "OUT" else a for a in TOOL_ARGS[tool]]
        out = run(script(tool), *args)
        assert out.returncode == 2 and "a_file' is an existing file, not a directory" in out.stderr, out.stderr
        assert "Traceback" not in out.stderr
