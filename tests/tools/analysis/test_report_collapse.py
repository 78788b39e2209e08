"""The report's collapse leads with the window chosen from the data; the fit to every point
follows, marked REJECTED when its chi2 p-value is below 0.01. A synthetic archive follows the
scaling only inside |phi - phi_J| <= 0.0105, rate <= 1e-4 (every other point times 1.25, a
hundred times its error)."""
import re

import numpy as np

from synthetic import LN_F, TRUTH, write_flow_archive
from test_report import REPORT, call

PHIS = np.round(np.arange(0.825, 0.8651, 0.005), 4)
RATES = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5)


def scaling_means(distortion):
    means = {}
    for phi in PHIS:
        for rate in RATES:
            x = (phi - TRUTH["phi_J"]) / rate ** (1 / TRUTH["znu"])
            value = rate ** TRUTH["q"] * np.exp(np.polyval(LN_F[::-1], x))
            outside = abs(phi - TRUTH["phi_J"]) > 0.0105 or rate > 1e-4
            means[(1024, float(phi), rate)] = value * (distortion if outside else 1.0)
    return means


def test_chosen_window_first_full_window_marked(tmp_path):
    path = write_flow_archive(tmp_path / "a.h5", "RD0", scaling_means(1.25), np.random.default_rng(8), seeds=4,
                              samples=100, noise=0.03)
    out = call(REPORT, path, tmp_path / "r", "--bootstrap", "0", "--degree", "2")
    assert out.returncode == 0, out.stderr
    md = open(tmp_path / "r" / "report.md").read()
    sections = [m.start() for m in re.finditer(r"^#+ Scaling collapse: RD0, pressure", md, re.M)]
    assert len(sections) == 2, md[:3000]
    first, second = md[sections[0]:sections[1]], md[sections[1]:]
    assert first.startswith("## Scaling collapse: RD0, pressure\n") and "Window (window chosen from the data)" in first
    window = re.search(r"phi ([0-9.]+)\.\.([0-9.]+), rate ([0-9.e-]+)\.\.([0-9.e-]+)", first)
    lo, hi, rate_max = float(window.group(1)), float(window.group(2)), float(window.group(4))
    assert TRUTH["phi_J"] - 0.0105 <= lo and hi <= TRUTH["phi_J"] + 0.0105 and rate_max <= 1e-4
    assert second.startswith("### Scaling collapse: RD0, pressure, every point (REJECTED)")
    assert "REJECTED: chi2/dof = " in second and "collapse_RD0_pressure_full.png" in second
    row = re.search(r"\| collapse RD0 pressure \(full window\) \| phi_J \|[^\n]*REJECTED \| ([0-9.e-]+) \|", md)
    assert row and float(row.group(1)) < 0.01, md[:3000]
    # the chosen window's row comes first in the table of fitted values
    assert md.index("| collapse RD0 pressure | phi_J |") < md.index("| collapse RD0 pressure (full window) | phi_J |")


def test_full_window_alone_when_every_point_scales(tmp_path):
    path = write_flow_archive(tmp_path / "a.h5", "RD0", scaling_means(1.0), np.random.default_rng(9), seeds=4,
                              samples=100, noise=0.03)
    out = call(REPORT, path, tmp_path / "r", "--bootstrap", "0", "--degree", "2")
    assert out.returncode == 0, out.stderr
    md = open(tmp_path / "r" / "report.md").read()
    assert "(full window)" not in md and "every point (REJECTED)" not in md
    assert f"phi {PHIS.min():g}..{PHIS.max():g}" in md
    # --full-window: every point only, no window chosen
    out = call(REPORT, path, tmp_path / "f", "--bootstrap", "0", "--degree", "2", "--full-window")
    md = open(tmp_path / "f" / "report.md").read()
    assert out.returncode == 0 and "Window (every point (full window))" in md and "chosen from the data" not in md
