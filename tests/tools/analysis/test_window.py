"""choose_window: the critical window chosen from the data. Synthetic flow curves follow the
known scaling function (3 % log-normal noise per replica, 8 seeds) only inside a window
|phi - phi_J| <= 0.0105, rate <= 1e-4; outside it every point is multiplied by 1.25 (ln 1.25
= 0.22, twenty times a point's error). The chosen window must lie inside the true one, be
acceptable, and its fit recover phi_J, q and znu within 4 standard errors for every noise
seed; data that follow the scaling everywhere keep every point; data that follow it nowhere
are flagged."""
import numpy as np
import pytest

import jamsim_analysis as ja
from jamsim_analysis.errors import AnalysisError
from synthetic import TRUTH, flow_replicas

PHIS = np.round(np.arange(0.815, 0.8751, 0.005), 4)
RATES = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)
HALF_WIDTH, RATE_MAX = 0.0105, 1e-4


def points(replicas):
    return ja.collapse_points(ja.group_averages(replicas, ["pressure"]), "pressure")


def distorted(seed):
    r = flow_replicas(np.random.default_rng(seed), phis=PHIS, rates=RATES)
    outside = (np.abs(r["phi"] - TRUTH["phi_J"]) > HALF_WIDTH) | (r["rate"] > RATE_MAX)
    r.loc[outside, "pressure"] *= 1.25
    return r


@pytest.mark.parametrize("seed", range(3))
def test_window_excludes_the_distorted_points(seed):
    choice = ja.scaling.choose_window(points(distorted(seed)), degree=2, level=0.01)
    assert choice.acceptable, choice.describe()
    assert choice.phi_min >= TRUTH["phi_J"] - HALF_WIDTH and choice.phi_max <= TRUTH["phi_J"] + HALF_WIDTH
    assert choice.rate_max <= RATE_MAX
    for name in ("phi_J", "q", "znu"):
        pull = (choice.fit.values[name] - TRUTH[name]) / choice.fit.errors[name]
        assert abs(pull) < 4, (name, pull, choice.describe())
    assert len(choice.tried) <= 400 and (choice.tried["p_value"] < 0.01).any()


def test_window_keeps_every_point_when_all_scale():
    pts = points(flow_replicas(np.random.default_rng(11)))
    choice = ja.scaling.choose_window(pts, degree=2, level=0.01)
    assert choice.acceptable and len(choice.fit.points) == len(pts), choice.describe()


def test_window_flags_data_that_never_scale():
    r = flow_replicas(np.random.default_rng(5), phis=PHIS, rates=RATES)
    scatter = np.random.default_rng(6).normal(0, 0.3, size=(len(PHIS), len(RATES)))
    index = {(p, q): scatter[i, j] for i, p in enumerate(np.round(PHIS, 5)) for j, q in enumerate(RATES)}
    r["pressure"] *= np.exp([index[(p, q)] for p, q in zip(r["phi"], r["rate"])])
    choice = ja.scaling.choose_window(points(r), degree=2, level=0.01)
    assert not choice.acceptable and "no window acceptable" in choice.describe()


def test_window_needs_three_rates():
    r = flow_replicas(np.random.default_rng(1), rates=(1e-4, 1e-5))
    with pytest.raises(AnalysisError, match="at least 3 shear rates"):
        ja.scaling.choose_window(points(r))
