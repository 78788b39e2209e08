"""Steady-state averages of several groups compared at the state points they share: two models
(RD0 against CD0 at phi = 0.84, rate = 1e-4), two archives (code versions, settings), any
number of rates, one included.

Groups are labelled by model (default) or by archive file. At each state point (N, phi, rate)
held by two or more groups, every pair (a, b) of groups is compared for each observable:

    difference       = mean_a - mean_b (seed averages, stats.group_averages)
    difference_error = sqrt(error_a^2 + error_b^2), the 1-sigma errors of the tables
    sigmas           = |difference| / difference_error

and tested for equal means, two-sided:

    Welch t (both groups with >= 2 seeds): t = difference / sqrt(s_a^2/k_a + s_b^2/k_b) over
      the replica means (s^2 their variance between seeds, k the seeds; the spread between
      seeds holds the time noise and the seed-to-seed offsets alike), with the
      Welch-Satterthwaite degrees of freedom nu = (v_a + v_b)^2 / (v_a^2/(k_a-1) + v_b^2/(k_b-1)),
      v = s^2/k, and p = 2 P(T_nu > |t|).
    t of the time errors (a group with one seed): t = difference / sqrt(e_a^2 + e_b^2) with
      e the one-seed group's time error (the only error one seed has; stats `_error_time`)
      and the other group's 1-sigma error, nu = Satterthwaite's dof from the time errors' own
      dof (`_error_dof`; a time error from a window of few independent samples is itself
      uncertain, and with a normal reference such tests alarmed at 6.7-7.8% for a 5% level,
      and at 9.8-13.1% with the time errors before their correction), and p = 2 P(T_nu > |t|).
      Its t can differ from `sigmas`, which divides by the tables' 1-sigma errors (a one-seed
      group's widened by its t factor).

The p-values of one comparison (every state point, pair and observable) are adjusted for
multiplicity by Holm's step-down method; a difference is significant when its adjusted p is
below alpha (default 0.05).
"""
import dataclasses
import itertools
import os

import numpy as np
import pandas as pd
from scipy import stats as sps

from . import stats
from .errors import AnalysisError

POINT = ("N", "phi", "rate")
ALPHA = 0.05


def holm(p):
    """Holm-Bonferroni adjusted p-values (same order as p)."""
    p = np.asarray(p, float)
    m = len(p)
    order = np.argsort(p)
    adjusted = np.empty(m)
    running = 0.0
    for rank, k in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[k]))
        adjusted[k] = running
    return adjusted


def welch(mean_a, var_a, k_a, mean_b, var_b, k_b):
    """Welch's t test of equal means from the means, the sample variances (ddof 1) and the
    sizes of two samples: (t, nu, two-sided p)."""
    va, vb = var_a / k_a, var_b / k_b
    se2 = va + vb
    d = mean_a - mean_b
    if not se2 > 0:
        return (0.0 if d == 0 else np.copysign(np.inf, d)), np.nan, (1.0 if d == 0 else 0.0)
    nu = se2 ** 2 / (va ** 2 / (k_a - 1) + vb ** 2 / (k_b - 1))
    t = d / np.sqrt(se2)
    return float(t), float(nu), float(2 * sps.t.sf(abs(t), nu))


# Said with every comparison that holds a one-seed test: a single seed's time error misses the
# spread between seeds (the offsets of its start), which only two or more seeds measure.
ONE_SEED_CAUTION = ("Caution: the tests of a group with one seed rest on its time error alone, which misses the "
                    "spread between seeds, so they alarm more often than their level where seeds differ beyond "
                    "their time noise: run two or more seeds per group for Welch's t.")


def time_error_test(difference, errors, dofs):
    """Two-sided t test of a difference whose error is the sum in quadrature of `errors`, each
    estimated with `dofs` (infinite: known): (t, Satterthwaite's nu, p)."""
    se2 = float(np.sum(np.asarray(errors, float) ** 2))
    if not (np.isfinite(se2) and se2 > 0):
        return np.nan, np.nan, np.nan
    dof = stats.time_error_dof(errors, dofs)
    t = difference / np.sqrt(se2)
    p = 2 * (sps.t.sf(abs(t), dof) if np.isfinite(dof) else sps.norm.sf(abs(t)))
    return float(t), float(dof), float(p)


@dataclasses.dataclass
class AveragesComparison:
    """averages: each group's seed averages at the shared state points (label, N, phi, rate,
    seeds, <obs>, <obs>_error); differences: one row per (state point, pair, observable)
    (see the module); alpha: the level; observables; labels (the groups in order)."""
    averages: pd.DataFrame
    differences: pd.DataFrame
    alpha: float
    observables: list
    labels: list

    @property
    def significant(self):
        return self.differences[self.differences["significant"]]

    def statement(self):
        """One sentence per difference, then the verdict."""
        d = self.differences
        lines = []
        for r in d.itertuples(index=False):
            test = (f"Welch t = {r.statistic:.2f}, nu = {r.dof:.1f}" if r.test == "Welch t"
                    else f"t = {r.statistic:.2f}, nu = {r.dof:.1f} (one seed: time errors)")
            lines.append(f"{r.observable} at N = {int(r.N)}, phi = {r.phi:g}, rate = {r.rate:g}: "
                         f"{r.group_a} - {r.group_b} = {r.difference:.4g} +- {r.difference_error:.2g} "
                         f"({r.sigmas:.1f} sigma; {test}, p = {r.p_value:.3g}, Holm-adjusted "
                         f"{r.p_adjusted:.3g}): {'significant' if r.significant else 'not significant'} "
                         f"at the {self.alpha:g} level.")
        n_sig = int(d["significant"].sum())
        lines.append(f"{n_sig} of {len(d)} differences significant at the {self.alpha:g} level "
                     f"(two-sided; Holm's adjustment over the {len(d)} tests of this comparison).")
        if (d["test"] == "t of time errors").any():
            lines.append(ONE_SEED_CAUTION)
        return " ".join(lines)


def compare_averages(groups, observables, label="model", alpha=ALPHA, replica_table=None):
    """Compare the seed averages `groups` (stats.group_averages output; a `label` column names
    each group, default the model) at the state points two or more groups share.

    The Welch test needs each group's variance between seeds: from replica_table (the
    replica means, stats.replica_averages, with the same `label` column) when given, else
    from `<obs>_error_seeds` (s/sqrt(k)). Raises AnalysisError when fewer than two groups or
    no shared state point."""
    if label not in groups:
        raise AnalysisError(f"the averages have no column '{label}' to tell the groups apart")
    keys = [k for k in POINT if k in groups and not groups[k].isna().all()]
    labels = list(dict.fromkeys(groups[label]))
    if len(labels) < 2:
        raise AnalysisError(f"a comparison needs two groups; the data hold {labels or 'none'} ({label})")
    missing = [o for o in observables if o not in groups]
    if missing:
        raise AnalysisError(f"observable {', '.join(missing)} is not in the averages")
    spread = _seed_variances(replica_table, label, keys, observables)
    rows, shared = [], []
    for point, part in groups.groupby(keys, sort=True):
        point = point if isinstance(point, tuple) else (point,)
        here = [g for g in labels if g in set(part[label])]
        if len(here) < 2:
            continue
        twice = part[label].duplicated()
        if twice.any():
            raise AnalysisError(f"group {part[label][twice].iloc[0]} has two rows at "
                                + ", ".join(f"{k} = {v:g}" for k, v in zip(keys, point))
                                + ": each group holds one model (choose one with --model)")
        shared.append(part)
        by = {g: part[part[label] == g].iloc[0] for g in here}
        for a, b in itertools.combinations(here, 2):
            ra, rb = by[a], by[b]
            ka, kb = int(ra["seeds"]), int(rb["seeds"])
            for o in observables:
                d = float(ra[o] - rb[o])
                err = float(np.hypot(ra[f"{o}_error"], rb[f"{o}_error"]))
                row = dict(zip(keys, point), observable=o, group_a=a, group_b=b, mean_a=float(ra[o]),
                           error_a=float(ra[f"{o}_error"]), seeds_a=ka, mean_b=float(rb[o]),
                           error_b=float(rb[f"{o}_error"]), seeds_b=kb, difference=d, difference_error=err,
                           relative_difference=d / float(rb[o]) if rb[o] != 0 else np.nan,
                           sigmas=abs(d) / err if err > 0 else np.nan)
                if ka >= 2 and kb >= 2:
                    va, vb = (spread.get((g,) + point + (o,), (np.nan, 0)) for g in (a, b))
                    va, vb = (v if n == k and n >= 2 else float(r[f"{o}_error_seeds"]) ** 2 * k
                              for (v, n), r, k in ((va, ra, ka), (vb, rb, kb)))
                    t, nu, p = welch(float(ra[o]), va, ka, float(rb[o]), vb, kb)
                    row.update(test="Welch t", statistic=t, dof=nu, p_value=p)
                else:
                    t, nu, p = time_error_test(d, *zip(*(_time_error(r, o) for r in (ra, rb))))
                    row.update(test="t of time errors", statistic=t, dof=nu, p_value=p)
                rows.append(row)
    if not rows:
        raise AnalysisError(f"no state point ({', '.join(keys)}) is held by two groups: nothing to compare "
                            f"(groups: {', '.join(map(str, labels))})")
    diff = pd.DataFrame(rows)
    finite = np.isfinite(diff["p_value"].to_numpy(float))
    adjusted = np.full(len(diff), np.nan)
    adjusted[finite] = holm(diff.loc[finite, "p_value"])
    diff["p_adjusted"] = adjusted
    diff["significant"] = diff["p_adjusted"] < alpha
    cols = [label] + keys + ["seeds"] + [c for o in observables for c in (o, f"{o}_error")]
    averages = pd.concat(shared)[cols].reset_index(drop=True)
    return AveragesComparison(averages, diff, alpha, list(observables), labels)


def _time_error(row, observable):
    """(error, dof) of a group in a one-seed test: a one-seed group's time error and its dof;
    a group of several seeds, its 1-sigma error (already widened for its seeds) as known."""
    if int(row["seeds"]) == 1 and f"{observable}_error_time" in row:
        return float(row[f"{observable}_error_time"]), float(row.get(f"{observable}_error_dof", np.inf))
    return float(row[f"{observable}_error"]), np.inf


def _seed_variances(replica_table, label, keys, observables):
    """{(label, *point, observable): (variance of the kept replica means (ddof 1), count)}."""
    if replica_table is None:
        return {}
    t = replica_table[replica_table["left_out"] == ""] if "left_out" in replica_table else replica_table
    out = {}
    for key, part in t.groupby([label] + list(keys), sort=False):
        for o in observables:
            v = part[o].to_numpy(float)
            out[tuple(key) + (o,)] = (float(np.var(v, ddof=1)) if len(v) >= 2 else np.nan, len(v))
    return out


def point_label(row, keys=POINT):
    parts = []
    for k in keys:
        if k in row and np.isfinite(row[k]):
            parts.append(f"N={int(row[k])}" if k == "N" else f"{k}={row[k]:g}")
    return " ".join(parts)


def write_tables(comparison, outdir, stem="compare"):
    """<stem>_averages.tsv and <stem>.tsv (the differences) in outdir: their paths."""
    a, d = (os.path.join(outdir, f"{stem}{s}.tsv") for s in ("_averages", ""))
    comparison.averages.to_csv(a, sep="\t", index=False)
    comparison.differences.to_csv(d, sep="\t", index=False)
    return a, d


def refuse_shared_replicas(table):
    """AnalysisError when two files of a `--by file` table (column `file`) hold the same replica
    (identity and seed: one trajectory), as a shard and its archive do: their difference was
    reported "not significant" as if the data were independent."""
    if not {"identity", "seed", "file"} <= set(table.columns):
        return
    shared = table[table.duplicated(["identity", "seed"], keep=False)]
    if shared["file"].nunique() > 1:
        r = shared.iloc[0]
        raise AnalysisError(f"--by file: {' and '.join(sorted(shared['file'].unique()))} hold the same replicas "
                            f"(N = {int(r['N'])}, phi = {r['phi']:g}, seed {int(r['seed'])}, ...): a shard and its "
                            "archive, or one run copied; compare independent archives")


def compared_replicas(archives, observables, by, filters):
    """The replica table of `jamsim-analyze compare` and its group keys: one table of all
    `archives` (groups by model), or with by == "file" one per archive with a `file` column
    (named by the file's stem, or its path when two stems agree; one file under two names and
    two files that share replicas are refused); then only the rows with filters' values
    ({"model": name, "N"/"phi"/"rate": number}; None keeps all), a value not in the data
    refused with the values that are."""
    from .archive import open_archives
    if by == "file":
        names = [os.path.splitext(os.path.basename(p))[0] for p in archives]
        if len(set(names)) < len(names):
            names = list(archives)
        if len(set(names)) < len(names):
            raise AnalysisError("--by file: an archive is given twice")
        for k, first in enumerate(archives):  # one file under two names compared with itself
            for second in archives[k + 1:]:
                if os.path.exists(first) and os.path.exists(second) and os.path.samefile(first, second):
                    raise AnalysisError(f"--by file: '{first}' and '{second}' are the same file: compare two "
                                        "different archives")
        tables = []
        for path, name in zip(archives, names):
            t = stats.replica_averages(open_archives([path]), observables)
            t.insert(0, "file", name)
            tables.append(t)
        table = pd.concat(tables, ignore_index=True)
        refuse_shared_replicas(table)
        keys = ("file",) + stats.KEYS
    else:
        table = stats.replica_averages(open_archives(archives), observables)
        keys = stats.KEYS
    for column, wanted in filters.items():
        if wanted is None:
            continue
        if column == "model":
            keep = table["model"] == wanted
        else:
            keep = np.isclose(table[column].astype(float), float(wanted), rtol=1e-9, atol=0)
        if not keep.any():
            values = ", ".join(f"{v:g}" if isinstance(v, float) else str(v)
                               for v in sorted(table[column].dropna().unique()))
            raise AnalysisError(f"--{column} {wanted}: not in the data ({column}: {values})")
        table = table[keep]
    return table, keys
