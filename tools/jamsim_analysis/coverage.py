"""Coverage of the error bars: synthetic campaigns with a known truth, analysed as jamsim's
are, and how often the 1-sigma intervals cover the truth (68.27% when they are right).

Each replica's series is value * (1 + rel * (b + x_t)): x an AR(1) series of unit variance
and coefficient `a` (tau_int = (1 + a) / (2 (1 - a)) samples), b a seed-to-seed offset with
standard deviation `offset` times the time error of one replica's mean. Its mean and time
error come from stats.mean_with_error, the seed averages from stats.group_averages (rows
"group average": `<obs>_error`; "fit weight": `<obs>_error_fit`, the seed-to-seed variance
pooled over the campaign's points), and the fits take those as they take a real campaign's:
  collapse   scaling.fit_collapse of O = rate^q exp(P(x)) (phi_J, q, znu; degree 2)
  Newtonian  rheology.newtonian_divergence of O = A rate (phi_J - phi)^-beta (phi_J given)
  Bagnold    rheology.bagnold_analysis of O = A rate^2 d^-beta (1 + c d) (phi_J given)
Run: python3 -m jamsim_analysis.coverage [--campaigns 1000] (from tools/); short windows:
--samples 121 --tau 4.5 (13 independent samples; with --seeds 1 the one-seed error, which
rests on the time error and its dof alone).
"""
import argparse
import dataclasses
import sys

import numpy as np
import pandas as pd
from scipy.signal import lfilter

from . import rheology, scaling, stats
from .errors import AnalysisError

ONE_SIGMA = stats.ONE_SIGMA
COLLAPSE = {"phi_J": 0.8433, "q": 0.28, "znu": 3.5}
LN_F = (0.5, 2.0, -0.8)  # ln F(x), coefficients low to high
NEWTONIAN = {"beta": 2.6, "A": 0.02}
BAGNOLD = {"beta": 5.0, "A": 1e-4, "c": -4.0}
PHI_J = 0.8433


@dataclasses.dataclass
class Spec:
    """The synthetic series: samples n, AR(1) coefficient a, relative noise rel per sample,
    offset = seed-to-seed standard deviation in units of one replica's time error."""
    n: int = 400
    a: float = 0.8
    rel: float = 0.05
    offset: float = 1.0

    @property
    def time_error(self):
        return self.rel * np.sqrt((1 + self.a) / (1 - self.a) / self.n)


def ar1(rng, m, n, a):
    """m stationary AR(1) series of n samples, unit variance."""
    eps = rng.normal(size=(m, n))
    eps[:, 0] /= np.sqrt(1 - a * a)
    return lfilter([np.sqrt(1 - a * a)], [1.0, -a], eps, axis=1)


def replicas(rng, points, seeds, spec):
    """Replica table (as stats.replica_averages gives) of `points` (DataFrame phi, rate,
    value) with `seeds` replicas each."""
    m = len(points) * seeds
    offsets = rng.normal(size=(m, 1)) * spec.offset * spec.time_error / spec.rel
    series = 1 + spec.rel * (offsets + ar1(rng, m, spec.n, spec.a))
    rows = []
    for i, (phi, rate, value) in enumerate(points[["phi", "rate", "value"]].itertuples(index=False)):
        for s in range(seeds):
            est = stats.mean_with_error(value * series[i * seeds + s])
            rows.append(dict(model="RD0", N=1024, phi=phi, rate=rate, seed=s, pressure=est.mean,
                             pressure_error=est.error, pressure_dof=est.dof, left_out=""))
    return pd.DataFrame(rows)


def collapse_truth():
    rows = []
    for phi in np.round(np.linspace(0.825, 0.865, 5), 5):
        for rate in (1e-3, 1e-4, 3e-5, 1e-5):
            x = (phi - COLLAPSE["phi_J"]) / rate ** (1 / COLLAPSE["znu"])
            rows.append((phi, rate, rate ** COLLAPSE["q"] * np.exp(np.polyval(LN_F[::-1], x))))
    return pd.DataFrame(rows, columns=["phi", "rate", "value"])


def divergence_truth(power):
    truth = NEWTONIAN if power == 1 else BAGNOLD
    phis = np.round(np.linspace(0.80, 0.835, 5 if power == 1 else 6), 5)
    rows = []
    for phi in phis:
        d = PHI_J - phi
        for rate in (1e-5, 1e-4):
            rows.append((phi, rate, truth["A"] * rate ** power * d ** -truth["beta"] * (1 + truth.get("c", 0) * d)))
    return pd.DataFrame(rows, columns=["phi", "rate", "value"])


def _fit_rows(kind, seeds, fit, truth):
    """One row per parameter: covered with the fit's errors (scaled by the residuals, times
    t sqrt(chi2/dof): stats.residual_scale) and with the plain ones (the weights as given)."""
    inflate = np.sqrt(stats.residual_scale(fit.chi2, fit.dof))
    return [dict(quantity=f"{kind} {k}", seeds=seeds,
                 covered=abs(fit.values[k] - v) <= fit.errors[k],
                 covered_plain=abs(fit.values[k] - v) <= fit.errors[k] / inflate) for k, v in truth.items()]


TRUTHS = {"collapse": collapse_truth, "Newtonian": lambda: divergence_truth(1),
          "Bagnold": lambda: divergence_truth(2)}


def one_campaign(rng, seeds, spec, fits=True, kinds=tuple(TRUTHS)):
    """Coverage rows of one synthetic campaign: every group average (new and old error, and
    the pooled fit weight) and, with fits, every fitted parameter."""
    rows = []
    for kind in kinds:
        truth_points = TRUTHS[kind]()
        groups = stats.group_averages(replicas(rng, truth_points, seeds, spec), ["pressure"])
        merged = groups.merge(truth_points, on=["phi", "rate"])
        dev = (merged["pressure"] - merged["value"]).abs()
        for d, e, e_old, e_fit in zip(dev, merged["pressure_error"], merged["pressure_error_seeds"],
                                      merged["pressure_error_fit"]):
            rows.append(dict(quantity="group average", seeds=seeds, covered=d <= e, covered_plain=d <= e_old))
            rows.append(dict(quantity="fit weight", seeds=seeds, covered=d <= e_fit, covered_plain=d <= e_old))
        if not fits:
            continue
        try:
            if kind == "collapse":
                fit = scaling.fit_collapse(scaling.collapse_points(groups, "pressure"), degree=2,
                                           start=tuple(COLLAPSE.values()), multistart=False)
                rows += _fit_rows(kind, seeds, fit, COLLAPSE)
            else:
                func = rheology.newtonian_divergence if kind == "Newtonian" else rheology.bagnold_analysis
                _, fit = func(groups, phi_j=PHI_J)
                rows += _fit_rows(kind, seeds, fit, NEWTONIAN if kind == "Newtonian" else BAGNOLD)
        except AnalysisError:
            rows.append(dict(quantity=f"{kind} failed", seeds=seeds, covered=False, covered_plain=False))
    return rows


def coverage_table(campaigns, seed_counts=(2, 4, 16), spec=None, fits=True, seed=12345, kinds=tuple(TRUTHS)):
    """DataFrame quantity, seeds, offset, trials, coverage, binomial error (of 68.27%), and
    coverage_plain: of the group averages and fit weights with the plain standard error over
    seeds (the old estimator), of the fits with the weights as given (without the residual
    scaling). kinds: the synthetic campaigns (and their fits) among TRUTHS."""
    spec = spec or Spec()
    rng = np.random.default_rng(seed)
    rows = []
    for k in seed_counts:
        for _ in range(campaigns):
            rows += one_campaign(rng, k, spec, fits, kinds)
    frame = pd.DataFrame(rows)
    out = frame.groupby(["quantity", "seeds"], sort=False).agg(
        trials=("covered", "size"), coverage=("covered", "mean"), coverage_plain=("covered_plain", "mean")).reset_index()
    out["binomial_error"] = np.sqrt(ONE_SIGMA * (1 - ONE_SIGMA) / out["trials"])
    out.insert(2, "offset", spec.offset)
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description="Coverage of the 1-sigma error bars of seed averages and fits "
                                "over synthetic campaigns (AR(1) series with a seed-to-seed offset).")
    p.add_argument("--campaigns", type=int, default=1000, help="synthetic campaigns per seed count")
    p.add_argument("--seeds", default="2,4,16", help="seed counts, comma separated")
    p.add_argument("--offset", type=float, default=1.0,
                   help="seed-to-seed offset, in units of one replica's time error")
    p.add_argument("--samples", type=int, default=Spec.n, help="samples per replica window")
    p.add_argument("--tau", type=float, default=(1 + Spec.a) / (2 * (1 - Spec.a)),
                   help="integrated autocorrelation time of the series, in samples")
    p.add_argument("--no-fits", action="store_true", help="group averages only")
    p.add_argument("--rng-seed", type=int, default=12345, help="seed of the random numbers")
    a = p.parse_args(argv)
    spec = Spec(n=a.samples, a=(2 * a.tau - 1) / (2 * a.tau + 1), offset=a.offset)
    table = coverage_table(a.campaigns, tuple(int(s) for s in a.seeds.split(",")), spec, not a.no_fits, a.rng_seed)
    with pd.option_context("display.width", 200, "display.max_rows", 200):
        print(table.to_string(index=False, float_format=lambda v: f"{v:.3f}"))
    bad = table[(table["coverage"] - ONE_SIGMA).abs() > 0.03]
    print(f"target {ONE_SIGMA:.3f} +- 0.030: " + ("every row inside" if bad.empty else f"{len(bad)} rows outside"))
    return 0 if bad.empty else 1


if __name__ == "__main__":
    sys.exit(main())
