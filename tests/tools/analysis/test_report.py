"""The commands on real archives made by jamsim: the report of a flow campaign and of a RAND
campaign, bad input refused with one message and a non-zero exit, --help saying what each
command computes. The scripts run as processes where that matters (the report, a missing
file); the rest calls the same entry points in this process (an uncaught exception fails
the test as a traceback would)."""
import contextlib
import io
import os
import re
import subprocess
import types

import pytest

from conftest import ROOT
from jamsim_analysis import cli

PYTHON = "/usr/bin/python3"
REPORT = os.path.join(ROOT, "tools", "jamsim_report.py")
ANALYZE = os.path.join(ROOT, "tools", "jamsim_analyze.py")


def run(*args):
    return subprocess.run([PYTHON, *map(str, args)], capture_output=True, text=True)


def call(script, *args):
    """The script's entry point in this process: (returncode, stdout, stderr)."""
    main = cli.report_main if script == REPORT else cli.analyze_main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in args])
        except SystemExit as e:
            code = e.code
    return types.SimpleNamespace(returncode=code, stdout=out.getvalue(), stderr=err.getvalue())


def check_report(outdir):
    md = open(os.path.join(outdir, "report.md")).read()
    html = open(os.path.join(outdir, "report.html")).read()
    figures = re.findall(r"!\[[^]]*\]\(([^)]+)\)", md)
    assert figures and all(os.path.getsize(os.path.join(outdir, f)) > 5000 for f in figures)
    assert all(f in html for f in figures)
    return md


def test_report_of_a_flow_campaign(flow_archive, tmp_path):
    out = run(REPORT, flow_archive, tmp_path, "--bootstrap", "20")
    assert out.returncode == 0, out.stderr
    md = check_report(tmp_path)
    # fitted values with errors and chi2/dof, the window, the errors' method, left-out replicas
    row = re.search(r"\| collapse RD0 pressure \| phi_J \| ([^|]+) \| ([^|]+) \| ([^|]+) \| (\d+) \| ([^|]+)\|", md)
    assert row, md[:2000]
    value, error, chi2 = (float(row.group(k)) for k in (1, 2, 3))
    assert 0.7 < value < 1.0 and error > 0 and chi2 > 0
    assert "N = 64, phi 0.8..0.89" in row.group(5) and "errors: " in row.group(5)
    assert "Replicas left out:" in md and "## Analyses not run" in md
    assert "configuration.png" in md and "correlation.png" in md


def test_report_collapse_window(flow_archive, tmp_path):
    """--phi-min/--phi-max/--rate-max restrict the collapse to the critical region: the fit's
    note names the window of the points used, and a window with too few points is an
    analysis not run (with its reason), not a traceback."""
    out = call(REPORT, flow_archive, tmp_path / "w", "--bootstrap", "0", "--phi-min", "0.82",
               "--phi-max", "0.9")
    assert out.returncode == 0, out.stderr
    md = open(tmp_path / "w" / "report.md").read()
    row = re.search(r"\| collapse RD0 pressure \| phi_J \|[^\n]*N = 64, phi ([0-9.]+)\.\.([0-9.]+), rate", md)
    assert row, md[:2000]
    assert (float(row.group(1)), float(row.group(2))) == (0.83, 0.89)  # 0.80 left out
    for name, args, reason in (("r", ("--rate-max", "2e-3"), "at least 3 shear rates"),
                               ("e", ("--phi-min", "0.95"), "no \\(phi, rate\\) point")):
        out = call(REPORT, flow_archive, tmp_path / name, "--bootstrap", "0", *args)
        md = open(tmp_path / name / "report.md").read()
        assert re.search(r"\| collapse RD0 pressure \| [^\n]*" + reason, md), md[:3000]


def test_report_auto_window(flow_archive, tmp_path):
    """--auto-window: the report names the window chosen from the data, with its p-value and
    the windows tried, and the fit's note is of that window; given with an explicit window
    it is refused with one message and exit 2, for the report and the collapse command."""
    out = call(REPORT, flow_archive, tmp_path / "a", "--bootstrap", "0", "--auto-window")
    assert out.returncode == 0, out.stderr
    md = open(tmp_path / "a" / "report.md").read()
    chosen = re.search(r"Window chosen from the data \(--auto-window\): phi ([0-9.]+)\.\.([0-9.]+), "
                       r"rate <= ([0-9.e-]+) \((\d+) points, chi2/dof = [0-9.]+, p = ([0-9.e-]+)", md)
    assert chosen, md[:3000]
    lo, hi = float(chosen.group(1)), float(chosen.group(2))
    row = re.search(r"\| collapse RD0 pressure \| phi_J \|[^\n]*N = 64, phi ([0-9.]+)\.\.([0-9.]+), rate", md)
    assert row and (float(row.group(1)), float(row.group(2))) == (lo, hi)
    assert "| phi_min | phi_max | rate_max | points | chi2_per_dof | p_value | phi_J |" in md
    for script, args in ((REPORT, (flow_archive, tmp_path / "b", "--auto-window", "--phi-min", "0.8")),
                         (ANALYZE, ("collapse", flow_archive, tmp_path / "c", "--auto-window", "--rate-max", "1e-3"))):
        out = call(script, *args)
        assert out.returncode == 2 and "--auto-window chooses the window itself" in out.stderr, out.stderr
        assert "Traceback" not in out.stderr
    out = call(ANALYZE, "collapse", flow_archive, tmp_path / "d", "--auto-window")
    assert out.returncode == 0 and "window chosen from the data: phi" in out.stdout, out.stderr


def test_report_of_a_rand_campaign(rand_archive, tmp_path):
    out = call(REPORT, rand_archive, tmp_path)
    assert out.returncode == 0, out.stderr
    md = check_report(tmp_path)
    assert "| threshold RAND N=16 | mu |" in md and "pj.png" in md


def test_bad_input_gets_one_message_and_no_traceback(rand_archive, small_archive, tmp_path):
    cases = [
        ((ANALYZE, "collapse", rand_archive, tmp_path), "model RAND has no flow curves"),
        ((ANALYZE, "jamming", small_archive), "model RD0 is not a jamming protocol"),
        ((REPORT, tmp_path / "missing.h5", tmp_path / "r"), "missing.h5': no such file"),
        ((ANALYZE, "collapse", small_archive, tmp_path), "at least 3 shear rates"),
        ((ANALYZE, "collapse", small_archive, tmp_path, "--N", "32"), "N = 32 is not in the data"),
        ((ANALYZE, "newtonian", small_archive, tmp_path, "--phi-j", "0.79"), "points below phi_J"),
    ]
    for args, message in cases:
        out = run(*args) if "missing" in str(args[1]) else call(*args)
        assert out.returncode == 2, (args, out.stdout, out.stderr)
        assert message in out.stderr and "Traceback" not in out.stderr, (args, out.stderr)
        assert len(out.stderr.strip().splitlines()) == 1, out.stderr
    # the report of an archive that cannot be fitted writes what applies (averages, g_y, a
    # picture), exits 0 and says in its pages and on stdout why the fits did not run
    out = call(REPORT, small_archive, tmp_path / "r")
    assert out.returncode == 0 and out.stderr == "", out.stderr
    assert out.stdout.startswith("ran: steady-state averages") and "not run: collapse RD0 pressure: a " in out.stdout
    md = open(tmp_path / "r" / "report.md").read()
    assert "a collapse needs at least 3 shear rates" in md and "## Steady-state averages" in md


@pytest.mark.parametrize("command,phrase", [
    ((REPORT,), "P_J(phi, N)"), ((ANALYZE, "collapse"), "rate^q"), ((ANALYZE, "newtonian"), "Newtonian"),
    ((ANALYZE, "bagnold"), "Bagnold"), ((ANALYZE, "jamming"), "finite-size"), ((ANALYZE, "compare"), "joint"),
    ((ANALYZE, "correlation"), "g_y"), ((ANALYZE, "picture"), "contact"), ((ANALYZE, "averages"), "tau_int")])
def test_help_says_what_is_computed(command, phrase):
    out = call(*command, "--help")
    assert out.returncode == 0 and phrase in out.stdout.replace("\n", " "), out.stdout
