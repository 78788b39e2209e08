"""The seed averages' 1-sigma errors cover the truth 68.27% of the time: a small run of
jamsim_analysis.coverage (AR(1) series with a seed-to-seed offset equal to one replica's time
error, 2 and 4 seeds). Tolerance: 3 binomial standard errors of the coverage of a correct
interval over the trials of the smaller sample (a false failure about 3 times in 1000 per
row). The plain standard error over seeds (the estimator before the random-effects
combination) covers about 50% with 2 seeds, outside that tolerance: checked here too. The
fit weights (`<obs>_error_fit`, pooled seed-to-seed variance) cover as well, and so do the
Newtonian fit's errors with 2 seeds (the case where per-point weights resting on one degree
of freedom made the fits cover about 58%)."""
import numpy as np

from jamsim_analysis import coverage


def _tolerance(table):
    return 3 * np.sqrt(coverage.ONE_SIGMA * (1 - coverage.ONE_SIGMA) / table["trials"].min())


def test_seed_averages_cover_the_truth():
    table = coverage.coverage_table(40, seed_counts=(2, 4), fits=False, seed=7)
    assert set(table["quantity"]) == {"group average", "fit weight"}
    tolerance = _tolerance(table)
    assert tolerance < 0.04, tolerance
    for row in table.itertuples():
        assert abs(row.coverage - coverage.ONE_SIGMA) <= tolerance, (row, tolerance)
    two = table[(table["seeds"] == 2) & (table["quantity"] == "group average")].iloc[0]
    assert abs(two.coverage_plain - coverage.ONE_SIGMA) > tolerance, two


def test_newtonian_fit_covers_with_two_seeds():
    table = coverage.coverage_table(400, seed_counts=(2,), seed=11, kinds=("Newtonian",))
    fits = table[table["quantity"].str.startswith("Newtonian")]
    assert set(fits["quantity"]) == {"Newtonian beta", "Newtonian A"}
    tolerance = _tolerance(fits)
    assert tolerance < 0.075, tolerance
    for row in fits.itertuples():
        assert abs(row.coverage - coverage.ONE_SIGMA) <= tolerance, (row, tolerance)


def test_one_seed_error_of_a_short_window_covers_the_truth():
    """One seed, no seed-to-seed offset, windows of 121 samples at tau_int = 4.5 (13
    independent samples): the group error, the time error times Student's t for its dof,
    covers the truth 68.27% of the time within the tolerance. Before the time error was
    corrected for the sample mean and widened for its dof it covered 57%."""
    spec = coverage.Spec(n=121, a=0.8, offset=0.0)
    table = coverage.coverage_table(25, seed_counts=(1,), spec=spec, fits=False, seed=5)
    row = table[table["quantity"] == "group average"].iloc[0]
    tolerance = _tolerance(table)
    assert tolerance < 0.05, tolerance
    assert abs(row.coverage - coverage.ONE_SIGMA) <= tolerance, (row, tolerance)
