"""A fit whose chi2/dof is far from 1 (p-value below 0.01) is flagged in the report's table
and text, with its errors also inflated by sqrt(chi2/dof); a fit with honest error bars is
not flagged (the collapse's errors are scaled by the residuals, so the inflated column is
the error itself). Real collapse fits of synthetic flow curves (3% noise per replica, 8
seeds): the honest one takes the seed averages' errors, the bad one the same points with
errors ten times too small (chi2/dof about 100)."""
import numpy as np
from scipy import stats

import jamsim_analysis as ja
from jamsim_analysis import report
from synthetic import flow_replicas


def collapse(scale):
    pts = ja.collapse_points(ja.group_averages(flow_replicas(np.random.default_rng(3)), ["pressure"]), "pressure")
    pts["error"] *= scale
    return ja.fit_collapse(pts, degree=2)


def test_flagged_fit_in_table_and_text(tmp_path):
    good, bad = collapse(1.0), collapse(0.1)
    assert report.fit_quality(good.chi2, good.dof)[1] == ""
    p, flag = report.fit_quality(bad.chi2, bad.dof)
    assert p < report.FLAG_P and "too large" in flag
    rep = report.Report("flag", str(tmp_path))
    rep.fits += report.fit_rows("collapse good", good.values, good.errors, good.chi2, good.dof, "honest",
                                scaled="residuals")
    rep.fits += report.fit_rows("collapse bad", bad.values, bad.errors, bad.chi2, bad.dof, "errors / 10",
                                scaled="residuals")
    rows = {(r["analysis"], r["parameter"]): r for r in rep.fits}
    for name in ("phi_J", "q", "znu"):
        assert rows[("collapse good", name)]["flag"] == "" and np.isnan(rows[("collapse good", name)]["error_inflated"])
        r = rows[("collapse bad", name)]
        # the collapse's errors are scaled by the residuals, t sqrt(chi2/dof) with t the
        # Student-t factor of its dof: the inflated column is the error itself, and the plain
        # error (covariance of the weights as given) times t sqrt(chi2/dof)
        t = stats.t.ppf(0.5 + ja.stats.ONE_SIGMA / 2, bad.dof)
        plain = np.sqrt(bad.covariance[:3, :3].diagonal() / bad.chi2_per_dof) / t
        assert np.isclose(r["error_inflated"], bad.errors[name])
        if name == "phi_J":
            assert np.isclose(r["error_inflated"], plain[0] * t * np.sqrt(bad.chi2_per_dof))
        assert r["flag"].startswith("chi2/dof = ") and r["error_inflated"] > 0
    # the same errors without the built-in scaling (e.g. a bootstrap) are inflated here
    boot = report.fit_rows("bootstrap", {"q": 0.3}, {"q": 0.01}, chi2=400.0, dof=4, scaled=False)[0]
    assert np.isclose(boot["error_inflated"], 0.01 * 10.0)
    rep.write()
    md = open(tmp_path / "report.md").read()
    assert "| dof | note | p_value | error_inflated | flag |" in md
    text = md.split("## Analyses not run")[0]
    assert "Flagged fits" in text and "collapse bad: chi2/dof = " in text and "collapse good:" not in text
    assert "--auto-window" in text and "more seeds" in text and "lower rates" in text


def test_too_small_chi2_is_flagged_without_inflation():
    p, flag = report.fit_quality(0.5, 40)  # P(chi2_40 <= 0.5) is about 1e-40
    assert "too small" in flag
    row = report.fit_rows("x", {"a": 1.0}, {"a": 0.1}, 0.5, 40)[0]
    assert np.isnan(row["error_inflated"])
    assert report.fit_quality(40.0, 40)[1] == ""
