"""Trends of fitted values (jamsim_analysis.trends): the straight-line slope and its error
against exact statistics, verdicts on values that move toward, away from or not relative to
the published ones, the collapse fitted per N on synthetic flow curves whose phi_J shifts
with N, local Newtonian exponents of an exact power law with a correction, and the `sizes`
command and the report's section on a synthetic archive of three sizes."""
import numpy as np
import pandas as pd
import pytest
from scipy import integrate
from scipy import stats as sps

from jamsim_analysis import stats, trends
from synthetic import LN_F, TRUTH, flow_replicas, write_flow_archive
from test_report import ANALYZE, REPORT, call

PUBLISHED_Q = trends.PUBLISHED["q"]


def test_slope_interval_covers_the_true_slope_as_often_as_its_statistics_say():
    # Five points with unit errors (dof = 3): the error is widened by sqrt(chi2/dof) when
    # that exceeds 1; chi2 is independent of the slope's pull, so the coverage of
    # slope +- error is E[P(|Z| < sqrt(max(1, chi2_3 / 3)))].
    expected = integrate.quad(lambda c: sps.chi2.pdf(c, 3) * (2 * sps.norm.cdf(np.sqrt(max(1, c / 3))) - 1),
                              0, np.inf)[0]
    rng = np.random.default_rng(5)
    x, err, trials = np.array([8.0, 9, 10, 11, 12]), np.ones(5), 2000
    covered = 0
    for _ in range(trials):
        t = trends.fit_trend("q", x, 0.4 - 0.02 * x + err * rng.normal(size=5), err, PUBLISHED_Q)
        covered += abs(t.slope + 0.02) <= t.slope_error
    band = 3 * np.sqrt(expected * (1 - expected) / trials)
    assert abs(covered / trials - expected) <= band, (covered / trials, expected)


def test_verdicts():
    x, err = np.array([8.0, 10, 12]), np.full(3, 0.01)
    toward = trends.fit_trend("q", x, [0.40, 0.34, 0.29], err, PUBLISHED_Q)
    away = trends.fit_trend("q", x, [0.31, 0.36, 0.41], err, PUBLISHED_Q)
    flat = trends.fit_trend("q", x, [0.35, 0.352, 0.349], err, PUBLISHED_Q)
    assert toward.verdict() == "moves toward the published value" and toward.distance_z() < 2
    assert away.verdict() == "moves away from the published value" and away.distance_z() > 10
    assert flat.verdict() == "no trend beyond its errors"
    below = trends.fit_trend("phi_J", x, [0.836, 0.839, 0.842], np.full(3, 0.0005), trends.PUBLISHED["phi_J"])
    assert below.verdict() == "moves toward the published value"
    text = trends.statement(toward, "doubling of N", "N = 4096")
    assert text.startswith("q: moves toward the published value (0.28); slope -0.0275") and "per doubling of N" in text
    assert "at N = 4096 0.2883 +- " in text


def test_verdicts_judge_the_line_not_its_first_point():
    x = np.array([8.0, 10, 12])
    phi_j = trends.PUBLISHED["phi_J"]
    # starts inside the range and leaves it
    leaves = trends.fit_trend("phi_J", x, [0.8434, 0.8454, 0.8474], np.full(3, 1e-4), phi_j)
    assert leaves.verdict() == "leaves the published range" and leaves.distance_z() > 10
    # passes the published value and ends farther on the other side
    over = trends.fit_trend("q", x, [0.30, 0.20, 0.10], np.full(3, 0.01), PUBLISHED_Q)
    assert over.verdict() == "moves across the published range (overshoots it)"
    # a noisy first point does not set the direction: the line rises away from 0.28
    away = trends.fit_trend("q", x, [0.20, 0.25, 0.27], np.array([0.1, 0.002, 0.002]), PUBLISHED_Q)
    noisy = trends.fit_trend("q", x, [0.35, 0.26, 0.25], np.array([0.1, 0.002, 0.002]), PUBLISHED_Q)
    assert away.verdict() == "moves toward the published value"
    assert noisy.verdict() == "moves away from the published value", (noisy.first, noisy.last)
    into = trends.fit_trend("beta", x, [2.2, 2.45, 2.7], np.full(3, 0.02), trends.PUBLISHED["beta"])
    assert into.verdict() == "moves toward the published value, into its range" and into.distance_z() == 0
    with pytest.raises(trends.AnalysisError, match="needs values at 2 or more places .0 here"):
        trends.fit_trend("q", x, [0.28, 0.28, 0.28], np.full(3, 0.0), PUBLISHED_Q)  # no errors
    exact = trends.fit_trend("q", x, [0.28, 0.28, 0.28], np.full(3, 0.01), PUBLISHED_Q)
    assert exact.z == 0 and exact.verdict() == "no trend beyond its errors"


def size_replicas(rng):
    """Replica means of three sizes whose phi_J approaches TRUTH's as N^-1/2 (from below)."""
    parts = []
    for n in (256, 1024, 4096):
        truth = dict(TRUTH, phi_J=TRUTH["phi_J"] - 0.1 / np.sqrt(n))
        part = flow_replicas(rng, noise=0.02, seeds=4, truth=truth, ln_f=LN_F)
        part["N"] = n
        parts.append(part)
    return pd.concat(parts, ignore_index=True)


def test_collapse_per_size_finds_phi_j_rising_toward_the_published_value():
    table = size_replicas(np.random.default_rng(3))
    groups = stats.group_averages(table, ["pressure"])
    by_size = trends.collapse_by_size(table, groups, "pressure", (-np.inf, np.inf, np.inf), degree=2)
    assert list(by_size["N"]) == [256, 1024, 4096] and (by_size["left_out"] == "").all()
    truth = TRUTH["phi_J"] - 0.1 / np.sqrt(by_size["N"].to_numpy(float))
    pulls = (by_size["phi_J"] - truth) / by_size["phi_J_error"]
    lo, hi = sps.chi2.ppf([0.001, 0.999], 3)
    assert lo <= np.sum(pulls ** 2) <= hi, pulls
    found = {t.parameter: t for t in trends.size_trends(by_size)}
    assert found["phi_J"].verdict() == "moves toward the published value"
    assert found["q"].verdict() == "no trend beyond its errors" or found["q"].distance_z() < 3


def test_one_size_is_not_a_trend():
    table = size_replicas(np.random.default_rng(4))
    table = table[table["N"] == 1024]
    groups = stats.group_averages(table, ["pressure"])
    by_size = trends.collapse_by_size(table, groups, "pressure", (-np.inf, np.inf, np.inf), degree=2)
    try:
        trends.size_trends(by_size)
    except trends.AnalysisError as e:
        assert "1 system size" in str(e)
    else:
        raise AssertionError("a trend from one size")


def newtonian_groups(beta, c, phis=(0.80, 0.81, 0.82, 0.825, 0.83), phi_j=0.8434):
    """Exact Newtonian plateaus eta = d^-beta (1 + c d), 1% errors, at two rates."""
    rows = []
    for phi in phis:
        eta = (phi_j - phi) ** -beta * (1 + c * (phi_j - phi))
        for rate in (1e-6, 4e-6):
            rows.append(dict(model="RD0", N=1024, phi=phi, rate=rate, seeds=4, pressure=eta * rate,
                             pressure_error=0.01 * eta * rate))
    return pd.DataFrame(rows)


def test_local_newtonian_exponents_of_a_power_law():
    plateaus = trends.newtonian_plateaus(newtonian_groups(2.7, 0.0), 0.8434)
    local = trends.effective_newtonian_exponents(plateaus, 0.8434)
    assert np.allclose(local["beta_eff"], 2.7, rtol=1e-12) and len(local) == 4
    # two rates of 1% each per plateau: its error 1% / sqrt(2); two plateaus per exponent
    d = 0.8434 - np.array([0.80, 0.81, 0.82, 0.825, 0.83])
    assert np.allclose(local["beta_eff_error"], 0.01 / np.abs(np.diff(np.log(d))), rtol=1e-9)
    trend = trends.newtonian_trend(plateaus, 0.8434)
    assert abs(trend.slope) < 1e-9 and abs(trend.last - 2.7) < 1e-9
    assert trend.verdict() == "no trend beyond its errors"


def test_local_newtonian_exponents_rise_toward_phi_j_with_a_correction():
    # ln eta = -beta ln d + ln(1 + c d): beta_eff = beta - c d / (1 + c d), below beta far out
    plateaus = trends.newtonian_plateaus(newtonian_groups(2.7, 20.0), 0.8434)
    local = trends.effective_newtonian_exponents(plateaus, 0.8434)
    assert (np.diff(local["beta_eff"]) > 0).all() and (local["beta_eff"] < 2.7).all()
    trend = trends.newtonian_trend(plateaus, 0.8434)
    assert trend.verdict() == "moves toward the published value" and trend.slope > 0
    d = 0.8434 - 0.83
    assert abs(trend.last - (2.7 - 20 * d / (1 + 20 * d))) < 3 * trend.last_error


def test_two_plateaus_give_exponents_without_a_trend(tmp_path):
    groups = newtonian_groups(2.7, 0.0, phis=(0.81, 0.82))
    local, approach = trends.newtonian_approach(groups)
    assert len(local) == 2 and set(local["phi_J"]) == set(trends.PUBLISHED["phi_J"])
    assert all(t is None and "a trend needs values at 3 or more places (2 here)" in why for _, _, t, why in approach)
    statements = trends.approach_statements(approach)
    assert statements[0].startswith("at the published phi_J's lower end (0.8433): no trend (beta: a trend needs")


def three_size_archive(tmp_path):
    means = {}
    rng = np.random.default_rng(11)
    for _, r in size_replicas(rng).drop_duplicates(["N", "phi", "rate"]).iterrows():
        x = (r["phi"] - (TRUTH["phi_J"] - 0.1 / np.sqrt(r["N"]))) / r["rate"] ** (1 / TRUTH["znu"])
        means[(int(r["N"]), float(r["phi"]), float(r["rate"]))] = r["rate"] ** TRUTH["q"] * np.exp(
            np.polyval(LN_F[::-1], x))
    return write_flow_archive(tmp_path / "sizes.h5", "RD0", means, rng, seeds=3, samples=100, noise=0.02)


def test_sizes_command_and_report_section(tmp_path):
    path = three_size_archive(tmp_path)
    out = call(ANALYZE, "sizes", path, tmp_path / "s", "--degree", "2", "--bootstrap", "0")
    assert out.returncode == 0, out.stderr
    assert "phi_J: moves toward the published value (0.8433-0.8435)" in out.stdout, out.stdout
    assert "at N = 4096 " in out.stdout
    assert (tmp_path / "s" / "sizes.png").stat().st_size > 0
    assert list(pd.read_csv(tmp_path / "s" / "sizes.tsv", sep="\t")["N"]) == [256, 1024, 4096]
    rep = call(REPORT, path, tmp_path / "r", "--bootstrap", "0", "--degree", "2", "--full-window")
    assert rep.returncode == 0, rep.stderr
    md = open(tmp_path / "r" / "report.md").read()
    assert "## Fitted values by system size: RD0" in md and "sizes_RD0.png" in md
    assert "phi_J: moves toward the published value" in md


def test_sizes_refuses_a_model_not_in_the_data(tmp_path):
    path = three_size_archive(tmp_path)
    out = call(ANALYZE, "sizes", path, tmp_path / "s", "--model", "CD0", "--phi-min", "0.83", "--bootstrap", "0")
    assert out.returncode == 2 and "--model CD0 is not in" in out.stderr and "(models: RD0)" in out.stderr, out.stderr


def test_a_stricter_plateau_test_drops_a_thinning_phi(tmp_path):
    # phi = 0.83's two rates differ by 4% with 1% errors each: chi2 = 8 (1 dof), p = 0.005,
    # a plateau at the default level 0.001, not at 0.05
    groups = newtonian_groups(2.7, 0.0)
    at = (groups["phi"] == 0.83) & (groups["rate"] == 4e-6)
    groups.loc[at, "pressure"] *= 0.96
    groups.loc[at, "pressure_error"] *= 0.96
    assert 0.83 in set(trends.newtonian_plateaus(groups, 0.8434)["phi"])
    assert 0.83 not in set(trends.newtonian_plateaus(groups, 0.8434, p_min=0.05)["phi"])
    # the command passes its level on: a true plateau passes the default and fails a level
    # that almost no constant meets
    means = {(1024, phi, rate): rate * (0.8434 - phi) ** -2.7 for phi in (0.80, 0.81, 0.82, 0.825, 0.83)
             for rate in (1e-6, 4e-6)}
    path = write_flow_archive(tmp_path / "newton.h5", "RD0", means, np.random.default_rng(2), seeds=4, samples=100,
                              noise=0.02)
    default = call(ANALYZE, "newtonian", path, tmp_path / "n1", "--phi-j", "0.8434")
    assert default.returncode == 0 and "beta = 2.7" in default.stdout, default.stdout + default.stderr
    strict = call(ANALYZE, "newtonian", path, tmp_path / "n2", "--phi-j", "0.8434", "--plateau-p", "0.9999")
    assert strict.returncode == 2 and "0 points below phi_J" in strict.stderr, strict.stdout + strict.stderr
