"""The seed averages' 1-sigma errors cover the truth 68.27% of the time: a small run of
jamsim_analysis.coverage (AR(1) series with a seed-to-seed offset equal to one replica's time
error, 2 and 4 seeds). Tolerance: 3 binomial standard errors of the coverage of a correct
interval over the trials of the smaller sample (a false failure about 3 times in 1000). The
plain standard error over seeds (the estimator before the random-effects combination)
covers about 50% with 2 seeds, outside that tolerance: checked here too."""
import numpy as np

from jamsim_analysis import coverage


def test_seed_averages_cover_the_truth():
    table = coverage.coverage_table(40, seed_counts=(2, 4), fits=False, seed=7)
    assert set(table["quantity"]) == {"group average"}
    tolerance = 3 * np.sqrt(coverage.ONE_SIGMA * (1 - coverage.ONE_SIGMA) / table["trials"].min())
    assert tolerance < 0.04, tolerance
    for row in table.itertuples():
        assert abs(row.coverage - coverage.ONE_SIGMA) <= tolerance, (row, tolerance)
    two = table[table["seeds"] == 2].iloc[0]
    assert abs(two.coverage_plain - coverage.ONE_SIGMA) > tolerance, two
