"""The comparison of steady-state averages between groups (comparison.py, `jamsim_analyze.py
compare`, the report's section): Welch's t against scipy's, Holm's adjustment, the rate of
false alarms for equal means (with seed-to-seed offsets, where a z test on the tables'
1-sigma errors would alarm too often; with one seed of a short window, whose time error is
itself uncertain) at the level asked, a known offset found in synthetic
archives of two models at one rate (and of two archives of one model with --by file), and
the report of such archives: exit 0, the comparison written, the analyses not run named."""
import os

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

import jamsim_analysis as ja
from jamsim_analysis import comparison
from synthetic import write_flow_archive
from test_report import ANALYZE, REPORT, call

POINT = (1024, 0.84, 1e-4)


def test_welch_equals_scipy():
    rng = np.random.default_rng(2)
    for ka, kb in ((2, 2), (3, 7), (16, 4)):
        a, b = rng.normal(1.0, 0.1, ka), rng.normal(1.05, 0.3, kb)
        t, nu, p = comparison.welch(a.mean(), a.var(ddof=1), ka, b.mean(), b.var(ddof=1), kb)
        ref = sps.ttest_ind(a, b, equal_var=False)
        assert np.isclose(t, ref.statistic, rtol=1e-12) and np.isclose(p, ref.pvalue, rtol=1e-9)
        va, vb = a.var(ddof=1) / ka, b.var(ddof=1) / kb
        assert np.isclose(nu, (va + vb) ** 2 / (va ** 2 / (ka - 1) + vb ** 2 / (kb - 1)))


def test_holm_by_its_definition():
    rng = np.random.default_rng(3)
    p = rng.uniform(0, 0.2, 12)
    adjusted = comparison.holm(p)
    order = np.argsort(p)
    m = len(p)
    # the step-down definition: adjusted p_(i) = max over j <= i of min(1, (m - j + 1) p_(j))
    expected = np.maximum.accumulate(np.minimum(1, (m - np.arange(m)) * p[order]))
    assert np.allclose(adjusted[order], expected)
    assert np.all(adjusted >= p)


def replica_table(rng, groups, points, seeds, offset_sd, time_sd):
    """Replica means of equal-mean groups: mu = 1 per point, a seed offset N(0, offset_sd)
    and a time noise N(0, time_sd) with its error time_sd (the exact time error)."""
    rows = []
    for g in groups:
        for k in range(points):
            for s in range(seeds):
                value = 1.0 + offset_sd * rng.normal() + time_sd * rng.normal()
                rows.append(dict(model=g, N=64, phi=0.80 + 1e-4 * k, rate=1e-3, seed=s, pressure=value,
                                 pressure_error=time_sd, left_out=""))
    return pd.DataFrame(rows)


@pytest.mark.parametrize("seeds,offset_sd", [(2, 0.05), (3, 0.05), (4, 0.0), (6, 0.05), (1, 0.0)])
def test_equal_means_alarm_at_the_level(seeds, offset_sd):
    """Over 1000 state points with equal means, the fraction of raw p-values below 0.05 is
    never above 0.05 by more than 4 binomial standard deviations, and within 4 of 0.05 from 4
    seeds on (Welch's t is conservative with 2 or 3 seeds per group: its Satterthwaite
    degrees of freedom lie below the 2 (k - 1) of equal variances) and for the test of one
    seed with exact time errors (infinite dof: a z test)."""
    rng = np.random.default_rng(10 + seeds)
    table = replica_table(rng, ("A", "B"), 1000, seeds, offset_sd, 0.01)
    groups = ja.group_averages(table, ["pressure"])
    cmp = comparison.compare_averages(groups, ["pressure"], replica_table=table)
    d = cmp.differences
    assert len(d) == 1000 and set(d["test"]) == {"Welch t" if seeds >= 2 else "t of time errors"}
    rate = float(np.mean(d["p_value"] < 0.05))
    sd = np.sqrt(0.05 * 0.95 / len(d))
    assert rate < 0.05 + 4 * sd, rate
    if seeds >= 4 or seeds == 1:
        assert rate > 0.05 - 4 * sd, rate
    # Holm's adjustment keeps the family-wise rate: 1000 null tests rarely give one alarm
    assert d["significant"].sum() <= 1
    if seeds == 2 and offset_sd > 0:
        # the 1-sigma errors of the tables with a normal reference alarm far too often here
        z_rate = float(np.mean(2 * sps.norm.sf(d["sigmas"]) < 0.05))
        assert z_rate > 0.05 + 3 * sd, z_rate


def two_models(tmp_path, rng, offset, seeds=4, name=""):
    a = write_flow_archive(tmp_path / f"rd0{name}.h5", "RD0", {POINT: 1e-3}, rng, seeds=seeds)
    b = write_flow_archive(tmp_path / f"cd0{name}.h5", "CD0", {POINT: 1e-3 * (1 + offset)}, rng, seeds=seeds)
    return a, b


@pytest.mark.parametrize("seed", range(3))
def test_known_offset_between_two_models_at_one_rate(tmp_path, seed):
    """RD0 against CD0 at phi = 0.84, rate = 1e-4 with 4 seeds: a 3 % offset (about 12
    errors of the difference) is significant in p and sigma, and the measured difference is
    within 4 errors of the truth; the command writes its tables and figure."""
    rng = np.random.default_rng(seed)
    a, b = two_models(tmp_path, rng, 0.03)
    out = call(ANALYZE, "compare", a, b, "--outdir", tmp_path / "out")
    assert out.returncode == 0, out.stderr
    d = pd.read_csv(tmp_path / "out" / "compare.tsv", sep="\t")
    assert len(d) == 2 and d["significant"].all() and (d["test"] == "Welch t").all()
    p = d[d["observable"] == "pressure"].iloc[0]
    assert (p["group_a"], p["group_b"]) == ("CD0", "RD0")
    assert abs(p["difference"] - 3e-5) < 4 * p["difference_error"]
    averages = pd.read_csv(tmp_path / "out" / "compare_averages.tsv", sep="\t")
    assert list(averages["model"]) == ["CD0", "RD0"] and (averages["seeds"] == 4).all()
    assert {"pressure", "pressure_error", "shear_stress", "shear_stress_error"} <= set(averages.columns)
    assert os.path.getsize(tmp_path / "out" / "compare.png") > 10000
    assert "2 of 2 differences significant" in out.stdout


def test_equal_means_of_two_archives_by_file(tmp_path):
    """Two archives of one model (the same campaign with other seeds): --by file compares them;
    equal means are not significant in 17 of 20 pairs at least (binomial, 5 % each: P(more
    than 3 alarms) < 0.02), a 5 % offset is significant."""
    rng = np.random.default_rng(7)
    alarms = 0
    for k in range(20):
        a = write_flow_archive(tmp_path / f"a{k}.h5", "RD0", {POINT: 1e-3}, rng, seeds=3, samples=100)
        b = write_flow_archive(tmp_path / f"b{k}.h5", "RD0", {POINT: 1e-3}, rng, seeds=3, samples=100, first_seed=3)
        run = call(ANALYZE, "compare", a, b, "--by", "file", "--observable", "pressure")
        assert run.returncode == 0, run.stderr
        alarms += "1 of 1 differences significant" in run.stdout
    assert alarms <= 3, alarms
    c = write_flow_archive(tmp_path / "c.h5", "RD0", {POINT: 1.05e-3}, rng, seeds=3, samples=100, first_seed=3)
    shared = write_flow_archive(tmp_path / "shared.h5", "RD0", {POINT: 1e-3}, rng, seeds=3, samples=100)
    run = call(ANALYZE, "compare", a, shared, "--by", "file", "--observable", "pressure")
    assert run.returncode == 2 and "a19 and shared hold the same replicas" in run.stderr, run.stderr
    run = call(ANALYZE, "compare", a, c, "--by", "file", "--observable", "pressure")
    assert run.returncode == 0 and "1 of 1 differences significant" in run.stdout, run.stdout
    assert "a19 - c = " in run.stdout or "c - a19 = " in run.stdout, run.stdout


def test_compare_refusals(tmp_path):
    rng = np.random.default_rng(1)
    a, b = two_models(tmp_path, rng, 0.0)
    other = write_flow_archive(tmp_path / "other.h5", "CD0", {(1024, 0.85, 1e-4): 1e-3}, rng)
    for args, message in (((a,), "a comparison needs two groups"),
                          ((a, other), "no state point"),
                          ((a, b, "--rate", "1e-3"), "--rate 0.001: not in the data")):
        out = call(ANALYZE, "compare", *args)
        assert out.returncode == 2 and message in out.stderr, (args, out.stderr)


def test_report_of_two_models_at_one_rate(tmp_path):
    """The report of RD0 and CD0 at one rate: exit 0, the averages and their comparison
    (table, statement, figure), the collapses listed as not run with the reason."""
    rng = np.random.default_rng(4)
    a, b = two_models(tmp_path, rng, 0.03)
    out = call(REPORT, a, b, tmp_path / "r")
    assert out.returncode == 0, out.stderr
    md = open(tmp_path / "r" / "report.md").read()
    assert "## Steady-state averages compared: CD0 against RD0" in md
    assert "Welch's t" in md and "2 of 2 differences significant" in md
    assert "| collapse RD0 pressure | a collapse needs at least 3 shear rates" in md
    assert "ran: steady-state averages; steady-state averages compared between models" in out.stdout
    assert os.path.getsize(tmp_path / "r" / "compare.png") > 10000
    assert len(pd.read_csv(tmp_path / "r" / "compare.tsv", sep="\t")) == 2


def test_report_without_finished_replicas_is_an_error(tmp_path):
    import h5py
    path = write_flow_archive(tmp_path / "x.h5", "RD0", {POINT: 1e-3}, np.random.default_rng(1))
    with h5py.File(path, "a") as f:
        f["replicas/status"][...] = 3
    out = call(REPORT, path, tmp_path / "r")
    assert out.returncode == 2 and "no finished replica" in out.stderr, out.stderr


def test_two_real_models_at_one_rate(jamsim, tmp_path_factory, flow_archive):
    """RD0 and CD0 run by jamsim at one state point (N = 64, phi = 0.84, rate = 1e-2, 4
    seeds): the command compares them with Welch's t; the report exits 0 with the comparison,
    g_y and a picture; --collapse is the joint collapse (and says it needs two models)."""
    from conftest import run_campaign
    work = str(tmp_path_factory.mktemp("compare"))
    a, b = (run_campaign(jamsim, work, f"analysis_compare_{m}") for m in ("rd0", "cd0"))
    out = call(ANALYZE, "compare", a, b, "--outdir", os.path.join(work, "c"))
    assert out.returncode == 0, out.stderr
    d = pd.read_csv(os.path.join(work, "c", "compare.tsv"), sep="\t")
    assert list(d["observable"]) == ["pressure", "shear_stress"] and set(d["test"]) == {"Welch t"}
    assert (d["seeds_a"] >= 2).all() and (d["seeds_b"] >= 2).all()
    assert np.all((d["p_value"] > 0) & (d["p_value"] <= 1)) and np.all(d["p_adjusted"] >= d["p_value"])
    out = call(REPORT, a, b, os.path.join(work, "r"))
    assert out.returncode == 0, out.stderr
    md = open(os.path.join(work, "r", "report.md")).read()
    assert "## Steady-state averages compared: CD0 against RD0" in md and "compare.png" in md
    assert "configuration.png" in md and "correlation.png" in md
    out = call(ANALYZE, "compare", "--collapse", flow_archive)
    assert out.returncode == 2 and "a joint collapse needs two models" in out.stderr, out.stderr


def test_a_group_with_two_rows_at_a_point_is_refused():
    rng = np.random.default_rng(5)
    table = replica_table(rng, ("A", "B"), 2, 3, 0.0, 0.01)
    table.loc[table["model"] == "A", "label"] = "one"
    table.loc[table["model"] == "B", "label"] = "one"
    groups = ja.group_averages(pd.concat([table, table.assign(label="two", model="A")]), ["pressure"],
                               keys=("label",) + ja.stats.KEYS)
    with pytest.raises(ja.AnalysisError, match="group one has two rows at N = 64"):
        comparison.compare_averages(groups, ["pressure"], label="label")


@pytest.mark.parametrize("n,a", [(121, 0.8), (400, 0.95), (60, 0.5)])
def test_one_seed_tests_of_short_windows_alarm_at_the_level(n, a):
    """One seed per group, each a stationary AR(1) series of n samples (tau_int = 4.5, 19.5
    and 1.5 samples: 13, 10 and 20 independent samples) with equal means at 1000 state points:
    its time error and dof from stats.mean_with_error, as replica_averages writes them. The
    raw p-values fall below 0.05 no more often than 0.05 plus 4 binomial standard deviations.
    A z test of the same time errors (normal reference) alarms in 6.7-7.8% of them, and with
    the error before its correction for the sample mean, 9.8-13.1%."""
    from jamsim_analysis import coverage
    rng = np.random.default_rng(int(n * 10 + a * 100))
    series = coverage.ar1(rng, 2000, n, a)
    rows = []
    for i, x in enumerate(series):
        est = ja.mean_with_error(x)
        rows.append(dict(model="AB"[i % 2], N=64, phi=0.80 + 1e-4 * (i // 2), rate=1e-3, seed=0, pressure=est.mean,
                         pressure_error=est.error, pressure_dof=est.dof, left_out=""))
    table = pd.DataFrame(rows)
    cmp = comparison.compare_averages(ja.group_averages(table, ["pressure"]), ["pressure"], replica_table=table)
    d = cmp.differences
    assert len(d) == 1000 and set(d["test"]) == {"t of time errors"}
    rate = float(np.mean(d["p_value"] < 0.05))
    assert rate < 0.05 + 4 * np.sqrt(0.05 * 0.95 / len(d)), rate
    assert rate > 0.01, rate  # 3.1-4.4% measured: a test that hardly ever alarms fails too


def test_one_seed_tests_carry_the_caution():
    """A comparison with a one-seed group says that its tests rest on time errors alone (they
    miss the spread between seeds); one with two seeds per group does not."""
    rng = np.random.default_rng(3)
    for seeds, cautioned in ((1, True), (2, False)):
        table = replica_table(rng, ("A", "B"), 5, seeds, 0.0, 0.01)
        cmp = comparison.compare_averages(ja.group_averages(table, ["pressure"]), ["pressure"], replica_table=table)
        assert (comparison.ONE_SEED_CAUTION in cmp.statement()) == cautioned
    groups = ja.group_averages(replica_table(rng, ("A",), 3, 1, 0.0, 0.01), ["pressure"])
    assert ja.stats.one_seed_note(groups).startswith("note: 3 of 3 state points have one seed")
    groups = ja.group_averages(replica_table(rng, ("A",), 3, 2, 0.0, 0.01), ["pressure"])
    assert ja.stats.one_seed_note(groups) == ""
