"""Position of the minimum of g_y(x) and its growth with falling rate."""
import numpy as np
import pytest

import jamsim_analysis as ja
from jamsim_analysis import correlations
from synthetic import pull_bounds


def test_minimum_of_a_parabola_is_exact_between_bins():
    x = np.arange(0, 10, 0.25)
    for x0 in (3.1, 4.37, 6.0):
        g = 0.2 * (x - x0) ** 2 - 0.3
        assert np.isclose(correlations.minimum_position(x, g), x0, atol=1e-12)


def test_minimum_of_damped_cosine_within_its_discretisation():
    """g = exp(-x/xi) cos(k x) has its first minimum at (pi - atan(1/(k xi)))/k; the parabola
    through 3 bins of width h errs by O(h^2) g'''/g'': below h/10 here."""
    x = np.arange(0, 20, 0.25)
    xi, k = 4.0, 0.5
    g = np.exp(-x / xi) * np.cos(k * x)
    exact = (np.pi - np.arctan(1 / (k * xi))) / k
    assert abs(correlations.minimum_position(x, g) - exact) < 0.025


def test_growth_fit_recovers_exponent():
    rate = np.array([1e-3, 3e-4, 1e-4, 3e-5, 1e-5])
    fits = []
    for s in range(5):
        rng = np.random.default_rng(s)
        truth = 0.5 * rate ** -0.3
        err = 0.05 * truth
        fits.append(ja.fit_minimum_growth(rate, truth + err * rng.normal(size=5), err))
    pulls = np.array([(f.a - 0.3) / f.a_error for f in fits])
    lo, hi = pull_bounds(len(fits))
    assert lo <= np.sum(pulls ** 2) <= hi, pulls
    with pytest.raises(ja.AnalysisError, match="at least 3 rates"):
        ja.fit_minimum_growth(rate[:2], [1, 2], [0.1, 0.1])
