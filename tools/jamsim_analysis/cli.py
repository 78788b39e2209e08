"""Command lines of the package: `jamsim-analyze COMMAND ...` (one analysis) and
`jamsim-report ARCHIVE... OUTDIR` (every analysis that fits); in a checkout
tools/jamsim_analyze.py and tools/jamsim_report.py. Bad input: one message on
stderr naming what is missing, exit status 2, no traceback."""
import argparse
import ast
import functools
import importlib.util
import math
import os
import sys
import types

from .command_support import (ANIMATION_SUFFIXES, FIGURE_SUFFIXES, describe_ids, output_directory, output_file,
                              prog_name, run_command, write_beside)
from .errors import AnalysisError

# numpy, pandas and the analysis modules (scipy, h5py, matplotlib: over a second) are imported
# by the functions that use them, after the arguments are parsed: --help needs none of them.

# Columns that hold counts or ids (stored as floats in a table that has NaN elsewhere).
_INTEGER_COLUMNS = ("replica", "N", "seed", "n_samples", "samples", "status", "force_evaluations", "predecessor",
                    "seeds", "replicas")


def _shown(table):
    """`table` for printing: count and id columns whose values are whole numbers as integers
    (N = 1024, not 1024.0); a column with a missing value stays as it is."""
    import numpy as np
    import pandas as pd
    out = table.copy()
    for c in _INTEGER_COLUMNS:
        if c in out and pd.api.types.is_float_dtype(out[c]):
            v = out[c].to_numpy()
            if np.all(np.isfinite(v)) and np.all(v == np.round(v)):
                out[c] = v.astype(np.int64)
    return out


def _print_table(table):
    """`table` on stdout, as _shown makes it, without the index."""
    print(_shown(table).to_string(index=False))


def _flow_archive(paths, model=None):
    """The archive(s), refused unless every model is a sheared-flow model and `model` (the
    --model option, when given) is one of them."""
    from .archive import open_archives
    run = open_archives(paths)
    if model is not None and model not in run.models:
        raise AnalysisError(f"--model {model} is not in {', '.join(paths)} (models: {', '.join(run.models)})")
    from . import report  # after the archives: a missing one is reported sooner
    other = sorted(set(run.models) - set(report.OVERDAMPED + report.MASSIVE))
    if other:
        raise AnalysisError(f"{', '.join(paths)}: model {', '.join(other)} has no flow curves; this analysis "
                            f"needs a sheared-flow campaign ({', '.join(report.OVERDAMPED + report.MASSIVE)})")
    return run


def _averages(archive, observables):
    from . import stats
    table = stats.replica_averages(archive, observables)
    return table, stats.group_averages(table, observables)


def cmd_summary(a):
    """One row per replica: parameters, status, force evaluations, wall time."""
    from .archive import open_archives
    run = open_archives(a.archives)
    cols = [c for c in ("replica", "model", "N", "phi", "rate", "seed", "status_name", "n_samples",
                        "force_evaluations", "wall_seconds", "failure_reason") if c in run.replicas]
    _print_table(run.replicas[cols])


def cmd_averages(a):
    """Steady windows, per-replica means with errors and tau_int, averages over seeds."""
    from . import stats
    from .archive import open_archives
    run = open_archives(a.archives)
    if a.output is not None:  # checked before the work, never an input, an archive or another kind of file
        output_file(a.output, "--output", inputs=a.archives)
        if os.path.splitext(a.output)[1].lower() not in (".tsv", ".txt"):
            raise AnalysisError(f"--output '{a.output}': a file name ending in .tsv or .txt (a table of "
                                "tab-separated values)")
    clocks = [o for o in a.observable if o in ("time", "strain")]
    if clocks:  # they grow through every run: no steady window ("no finished replica left to average")
        raise AnalysisError(f"--observable {clocks[0]} is not allowed: a quantity of the steady state, such as "
                            "pressure, shear_stress, energy_per_particle or contact_number (time and strain are "
                            "the series' clock)")
    table, groups = _averages(run, a.observable)
    cols = ["replica", "model", "N", "phi", "rate", "seed", "window_start", "samples", "drift_z", "drift_limit",
            "left_out"]
    for o in a.observable:
        cols += [o, f"{o}_error", f"{o}_tau", f"{o}_dof"]
    _print_table(table[[c for c in cols if c in table]])
    print()
    _print_table(groups)
    for note in (stats.one_seed_note(groups), stats.weak_drift_note(table)):
        if note:
            print(note)
    if a.output is not None:  # counts as integers, as printed (N 64, not 64.0)
        write_beside(a.output, lambda tmp: _shown(groups).to_csv(tmp, sep="\t", index=False))


def cmd_csv(a):
    """Per-replica steady means with errors and tau_int as a flat CSV (one row per replica)."""
    from . import stats, tables
    from .archive import open_archives
    run = open_archives(a.archives)
    observables = a.observable or [o for o in ("pressure", "shear_stress", "energy_per_particle",
                                                "contact_number", "packing_fraction") if o in run.observables()]
    unknown = sorted(set(observables) - set(run.observables()))
    if unknown:
        raise AnalysisError(f"--observable {', '.join(unknown)} is not allowed: the archives have "
                            f"{', '.join(run.observables())}")
    out = tables.write_means_csv(stats.replica_averages(run, observables), a.output, observables)
    print(f"{len(out)} replicas, {len(out.columns)} columns: {a.output}")


def _check_window_options(parser, a):
    """--auto-window and an explicit window exclude each other (argparse's error: exit 2)."""
    if a.auto_window and (math.isfinite(a.phi_min) or math.isfinite(a.phi_max) or math.isfinite(a.rate_max)):
        parser.error("--auto-window chooses the window itself: give it without --phi-min, --phi-max and --rate-max")


def _check_numbers(parser, a):
    """Options whose value no analysis can use: argparse's error (exit 2) naming the option and
    what is allowed, before any work. Each check applies where the command has the option."""
    def has(name):
        return getattr(a, name, None) is not None

    def refuse(option, value, allowed):
        parser.error(f"{option} = {value} is not allowed: {allowed}")

    if has("degree") and a.degree < 1:
        refuse("--degree", a.degree, "a whole number >= 1 (the degree of ln F(x); at 0 phi_J is not determined)")
    if has("correction_degree") and a.correction_degree < 0:
        refuse("--correction-degree", a.correction_degree, "a whole number >= 0 (the degree of Q(x))")
    if has("bootstrap") and (a.bootstrap < 0 or 0 < a.bootstrap < 10 or a.bootstrap > 100_000):
        refuse("--bootstrap", a.bootstrap, "0 (none) or from 10 to 100000 resamples (the error needs 10 converged "
               "fits; each resample is a whole fit)")
    if has("N") and a.N < 1:
        refuse("--N", a.N, "a system size >= 1")
    for name in ("phi_min", "phi_max", "rate_max"):
        if has(name) and math.isnan(getattr(a, name)):
            refuse("--" + name.replace("_", "-"), "nan", "a number (the collapse window)")
    for name in ("phi_min", "phi_max"):  # a window outside every packing fraction selected all or nothing
        if has(name) and math.isfinite(getattr(a, name)) and not 0 < getattr(a, name) < 1:
            refuse("--" + name.replace("_", "-"), getattr(a, name), "a packing fraction, 0 < phi < 1 (the collapse "
                   "window)")
    if has("phi_min") and has("phi_max") and not a.phi_min < a.phi_max:
        refuse("--phi-min", a.phi_min, f"below --phi-max = {a.phi_max} (the collapse window)")
    if has("rate_max") and not a.rate_max > 0:
        refuse("--rate-max", a.rate_max, "a rate > 0 (the collapse window)")
    if has("phi_j") and not 0 < a.phi_j < 1:
        refuse("--phi-j", a.phi_j, "a packing fraction, 0 < phi_J < 1")
    if has("plateau_p") and not 0 < a.plateau_p < 1:
        refuse("--plateau-p", a.plateau_p, "a p-value, 0 < p < 1")
    if has("alpha") and not 0 < a.alpha < 1:
        refuse("--alpha", a.alpha, "a test level, 0 < alpha < 1 (e.g. 0.05)")
    if has("start"):
        phi_j, q, znu = a.start
        if not (0 < phi_j < 1 and q > 0 and znu > 0 and math.isfinite(q) and math.isfinite(znu)):
            refuse("--start", " ".join(f"{v:g}" for v in a.start), "PHI_J in (0, 1), Q > 0 and ZNU > 0, finite")


def cmd_collapse(a):
    """Critical scaling collapse of p or sigma in the (phi, rate) plane."""
    import numpy as np
    import pandas as pd
    from . import figures, scaling
    output_directory(a.outdir, create=False)  # before the fit (a file there was refused after it)
    table, groups = _averages(_flow_archive(a.archives, a.model), [a.observable])
    if a.auto_window:
        every = scaling.collapse_points(groups, a.observable, a.N, model=a.model)
        choice = scaling.choose_window(every, a.degree, a.correction_degree if a.correction else -1,
                                       tuple(a.start), a.observable)
        print(f"window chosen from the data: {choice.describe()}")
        a.phi_min, a.phi_max, a.rate_max = choice.phi_min, choice.phi_max, choice.rate_max
    pts = scaling.collapse_points(groups, a.observable, a.N, (a.phi_min, a.phi_max), a.rate_max,
                                  model=a.model)
    fit = scaling.fit_collapse(pts, a.degree, a.correction_degree if a.correction else -1,
                               tuple(a.start), a.observable)
    if a.bootstrap:
        n = a.N if a.N is not None else groups.loc[groups["rate"] > 0, "N"].max()
        rows = table[table["N"] == n]
        if a.model is not None:
            rows = rows[rows["model"] == a.model]
        fit = scaling.bootstrap_collapse(rows, a.observable, fit, a.bootstrap)
    print(f"{a.observable}: {len(fit.points)} points, degree {a.degree}, "
          f"{'correction of degree %d' % a.correction_degree if a.correction else 'no correction'}; "
          f"errors: {fit.method}; chi2/dof = {fit.chi2_per_dof:.3f} ({fit.dof} dof)")
    for k, v in fit.values.items():
        print(f"  {k:6s} = {v:.5g} +- {fit.errors[k]:.2g}")
    output_directory(a.outdir)
    pts = fit.points
    label = (f"{a.observable}, {'window chosen from the data' if a.auto_window else 'window'}: phi "
             f"{pts['phi'].min():g}..{pts['phi'].max():g}, rate {pts['rate'].min():g}..{pts['rate'].max():g}, "
             f"{len(pts)} points")
    figures.collapse_figure(fit, os.path.join(a.outdir, f"collapse_{a.observable}.png"), label=label)
    pd.DataFrame([dict(parameter=k, value=v, error=fit.errors[k]) for k, v in fit.values.items()]
                 + [dict(parameter="chi2_per_dof", value=fit.chi2_per_dof, error=np.nan),
                    dict(parameter="points", value=len(fit.points), error=np.nan),
                    dict(parameter="dof", value=fit.dof, error=np.nan)]).to_csv(
        os.path.join(a.outdir, f"collapse_{a.observable}.tsv"), sep="\t", index=False)


def cmd_sizes(a):
    """Does the collapse move toward the published values as N grows, and the Newtonian
    beta as the points come closer to phi_J? The collapse of one window fitted at every N
    (the window given, else the one chosen from the data at the largest N), each value's
    trend in N, and the local Newtonian exponents with their trend; tables and a figure in
    OUTDIR (sizes.tsv, newtonian_local.tsv, sizes.png)."""
    import numpy as np
    import pandas as pd
    from . import figures, scaling, trends
    output_directory(a.outdir, create=False)  # before the fits
    table, groups = _averages(_flow_archive(a.archives, a.model), [a.observable])
    window = (a.phi_min, a.phi_max, a.rate_max)
    if not any(np.isfinite(window)):
        every = scaling.collapse_points(groups, a.observable, model=a.model)
        choice = scaling.choose_window(every, a.degree, -1, observable=a.observable)
        print(f"window chosen from the data at the largest N: {choice.describe()}")
        window = (choice.phi_min, choice.phi_max, choice.rate_max)
    by_size = trends.collapse_by_size(table, groups, a.observable, window, a.degree, a.bootstrap, a.model)
    _print_table(by_size)
    found = trends.size_trends(by_size)
    print("\n".join(trends.size_statements(by_size, found)))
    local, approach = pd.DataFrame(), []
    try:
        local, approach = trends.newtonian_approach(groups, by_size, model=a.model, observable=a.observable,
                                                    p_min=a.plateau_p)
        print()
        _print_table(local)
        print("\n".join(trends.approach_statements(approach)))
    except AnalysisError as e:
        print(f"local Newtonian exponents: not computed ({e})")
    output_directory(a.outdir)
    by_size.to_csv(os.path.join(a.outdir, "sizes.tsv"), sep="\t", index=False)
    written = ["sizes.tsv", "sizes.png"]
    if len(local):
        local.to_csv(os.path.join(a.outdir, "newtonian_local.tsv"), sep="\t", index=False)
        written.insert(1, "newtonian_local.tsv")
    figures.trends_figure(by_size, found, local, os.path.join(a.outdir, "sizes.png"))
    print(f"tables and figure in {a.outdir}: {', '.join(written)}")


def cmd_compare(a):
    """Steady-state averages of several groups (models; archives with --by file) compared at
    the state points (N, phi, rate) they share, one rate or many: each group's seed averages
    with errors, each difference with its error in sigmas and a two-sided test of equal means
    (Welch t over the replica means, t of the time errors with their dof for one seed; Holm's adjustment),
    a table (compare_averages.tsv, compare.tsv) and a figure (compare.png) in --outdir.
    --collapse: instead, the joint collapse of two models (shared phi_J, q, znu) against
    separate ones, with an F test (needs >= 3 rates)."""
    if a.collapse:
        return _compare_collapses(a)
    if a.outdir:  # checked before the work (it was refused after every table was printed)
        output_directory(a.outdir, "--outdir", create=False)
    from . import comparison, figures, report, stats
    filters = {"model": a.model, "N": a.N, "phi": a.phi, "rate": a.rate}
    table, keys = comparison.compared_replicas(a.archives, a.observable, a.by, filters)
    groups = stats.group_averages(table, a.observable, keys=keys)
    cmp = comparison.compare_averages(groups, a.observable, label=a.by, alpha=a.alpha, replica_table=table)
    _print_table(cmp.averages)
    print()
    _print_table(cmp.differences[[c for c in report.DIFFERENCE_COLUMNS if c in cmp.differences]])
    print()
    print(cmp.statement())
    if a.outdir:
        output_directory(a.outdir, "--outdir")
        comparison.write_tables(cmp, a.outdir)
        figures.comparison_figure(cmp, os.path.join(a.outdir, "compare.png"), replicas=table, label=a.by)
        print(f"tables and figure: {os.path.join(a.outdir, 'compare.tsv')}, compare_averages.tsv, compare.png")


def _compare_collapses(a):
    """RD0 against CD0 (or any two models): joint collapse with shared phi_J, q, znu against separate ones."""
    import pandas as pd
    from . import scaling
    observable = a.observable[0]
    _, groups = _averages(_flow_archive(a.archives), [observable])
    models = sorted(groups.loc[groups["rate"] > 0, "model"].unique())
    pts = pd.concat([scaling.collapse_points(groups, observable, a.N, model=m) for m in models])
    cmp = scaling.compare_collapses(pts, a.degree, observable=observable)
    for name, f in list(cmp.separate.items()) + [("joint", cmp.joint)]:
        print(f"{name:6s}: " + ", ".join(f"{k} = {f.values[k]:.4g} +- {f.errors[k]:.2g}" for k in ("phi_J", "q", "znu"))
              + f", chi2/dof = {f.chi2_per_dof:.2f}")
    print(cmp.statement())


def _divergence_command(a, power):
    from . import figures, rheology
    output_directory(a.outdir, create=False)  # before the fit
    _, groups = _averages(_flow_archive(a.archives, a.model), [a.observable])
    func = rheology.newtonian_divergence if power == 1 else rheology.bagnold_analysis
    plateau, fit = func(groups, a.observable, phi_j=a.phi_j, correction=a.correction, N=a.N, model=a.model,
                        p_min=a.plateau_p)
    _print_table(rheology.local_slopes(groups, a.observable))
    _print_table(plateau)
    print(", ".join(f"{k} = {v:.5g} +- {fit.errors[k]:.2g}" for k, v in fit.values.items())
          + f", chi2/dof = {fit.chi2_per_dof:.2f}")
    output_directory(a.outdir)
    figures.divergence_figure(plateau, fit, f"{a.observable}/rate^{power}",
                              os.path.join(a.outdir, f"divergence_{power}_{a.observable}.png"))


def cmd_newtonian(a):
    """eta = O/rate at its Newtonian plateau per phi < phi_J, fitted to (phi_J - phi)^-beta."""
    _divergence_command(a, 1)


def cmd_bagnold(a):
    """Local slopes (Newtonian/Bagnold), B = O/rate^2 at its plateau and its divergence (1 + c (phi_J - phi)) (phi_J - phi)^-beta."""
    _divergence_command(a, 2)


def cmd_jamming(a):
    """P_J(phi, N), thresholds per N and their finite-size scaling (phi_J(inf), nu)."""
    from . import jamming
    from .archive import open_archives
    states = jamming.static_states(open_archives(a.archives))
    _print_table(jamming.jamming_probability(states))
    thr = jamming.thresholds(states)
    _print_table(thr)
    for model in sorted(states["model"].unique()):
        fit = jamming.finite_size_scaling(thr[thr["model"] == model] if len(thr) else thr, a.correction)
        print(f"{model}: " + ", ".join(f"{k} = {v:.5g} +- {fit.errors[k]:.2g}" for k, v in fit.values.items())
              + f", chi2/dof = {fit.chi2_per_dof:.2f}")


def cmd_correlation(a):
    """x_min of g_y(x) per (model, N, phi, rate) over seeds and its growth x_min = A rate^-a."""
    from . import correlations
    run = _flow_archive(a.archives)
    _, grouped = correlations.correlation_minima(run)
    _print_table(grouped)
    for key, part in grouped.groupby(["model", "N", "phi"]):
        g = correlations.fit_minimum_growth(part["rate"], part["x_min"], part["x_min_error"])
        print(f"{key}: a = {g.a:.3f} +- {g.a_error:.3f}, chi2/dof = {g.chi2 / max(g.dof, 1):.2f}")


def cmd_picture(a):
    """Picture of one replica's final configuration with its contact-force network."""
    import numpy as np
    from . import pictures
    from .archive import open_archives
    run = open_archives(a.archives)
    output_file(a.output, "--output", a.archives, FIGURE_SUFFIXES)
    done = run.done()
    if a.replica not in set(done["replica"]):
        raise AnalysisError(f"--replica {a.replica} is not a finished replica (finished: "
                            f"{describe_ids(done['replica'].to_list())})")
    rep = run.replicas.iloc[a.replica]
    alpha = float(rep["alpha"]) if "alpha" in rep and np.isfinite(rep["alpha"]) else 2.0
    final, strain = run.final(a.replica), run.final_strain(a.replica)
    params = f"{rep['model']} N = {int(rep['N'])}, phi = {rep['phi']:g}" + (
        f", rate = {rep['rate']:g}" if "rate" in rep and np.isfinite(rep["rate"]) and rep["rate"] > 0 else "")
    net, ratt = pictures.draw_configuration(final, a.output, alpha, strain=strain,
                                            caption=f"replica {a.replica}: {params}")
    p, s = net.stress(final.box_side)
    print(f"{pictures.strain_text(strain, final.box_strain)}: {len(net.force)} contacts, {int(ratt.sum())} "
          f"rattlers, network p = {p:.6g}, sigma = {s:.6g}; {a.output}")


def cmd_frames(a):
    """psi6 per configuration frame of one replica, and an animated GIF of its frames."""
    import numpy as np
    from . import order, pictures
    from .archive import open_archives
    run = open_archives(a.archives)
    if a.animation:
        output_file(a.animation, "--animation", a.archives, ANIMATION_SUFFIXES)
    if a.replica not in set(run.replicas["replica"]):
        raise AnalysisError(f"replica {a.replica} is not in these files ({len(run.replicas)} replicas)")
    table = order.psi6_over_strain(run, a.replica)
    _print_table(table)
    if a.animation:
        rep = run.replicas.iloc[a.replica]
        alpha = float(rep["alpha"]) if "alpha" in rep and np.isfinite(rep["alpha"]) else 2.0
        drawn = pictures.animate_frames(run, a.replica, a.animation, alpha=alpha)
        print(f"{drawn} frames drawn: {a.animation}")


def _common(p, observable=True, size_help="system size (default: the largest)"):
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    if observable:
        p.add_argument("--observable", default="pressure", choices=["pressure", "shear_stress"],
                       help="the observable fitted (default pressure)")
    p.add_argument("--N", type=int, help=size_help)
    p.add_argument("--model", help="only this model")


def _window_options(p):
    p.add_argument("--phi-min", type=float, default=-math.inf, help="only points with phi >= this")
    p.add_argument("--phi-max", type=float, default=math.inf, help="only points with phi <= this")
    p.add_argument("--rate-max", type=float, default=math.inf, help="only points with rate <= this")


def _plateau_option(p):
    rheology = _module_text("rheology")
    p.add_argument("--plateau-p", type=float, default=rheology.PLATEAU_P,
                   help="level of the plateau test: the lowest rates whose O/rate^power agree with one constant at "
                   f"this chi2 p-value or above form the plateau (default {rheology.PLATEAU_P:g}; larger: stricter)")


@functools.lru_cache(maxsize=None)
def _module_text(name):
    """The package's module `name` for the parsers: the module once imported, else its docstring
    and literal constants read from its source (importing it takes pandas, scipy, matplotlib)."""
    full = f"{__package__}.{name}"
    if full in sys.modules:
        return sys.modules[full]
    spec = importlib.util.find_spec(full)
    source = spec.loader.get_source(full) if hasattr(spec.loader, "get_source") else None
    if source is None:  # installed without its source: import it
        return importlib.import_module(full)
    tree = ast.parse(source)
    text = {"__doc__": ast.get_docstring(tree, clean=False)}
    for node in tree.body:
        if (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)
                and node.targets[0].id.isupper()):
            try:
                text[node.targets[0].id] = ast.literal_eval(node.value)
            except ValueError:
                pass  # computed from other names: not a constant the parsers use
    return types.SimpleNamespace(**text)


def analyze_parser():
    # The modules' docstrings and constants under their names, read without importing them.
    comparison, correlations, jamming, order, pictures, rheology, scaling, tables, trends = map(
        _module_text, "comparison correlations jamming order pictures rheology scaling tables trends".split())
    ap = argparse.ArgumentParser(
        prog=prog_name("jamsim_analyze.py"),
        description="One analysis of jamsim campaign archives (shards and replica files too); "
        "COMMAND --help says what it computes and its options. jamsim_report.py ARCHIVE... OUTDIR runs every "
        "analysis that fits. Bad input: one message naming what is wrong, exit status 2.")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("summary", help=cmd_summary.__doc__, description=cmd_summary.__doc__)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p = sub.add_parser("averages", help=cmd_averages.__doc__, description=cmd_averages.__doc__)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p.add_argument("--observable", nargs="+", default=["pressure", "shear_stress"],
                   help="time-series columns averaged (default: pressure shear_stress)")
    p.add_argument("--output", help="TSV file of the averages over seeds (a name ending in .tsv or .txt)")
    p = sub.add_parser("csv", help=cmd_csv.__doc__, description=cmd_csv.__doc__ + " " + tables.__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p.add_argument("-o", "--output", required=True, help="CSV file to write (must not exist)")
    p.add_argument("--observable", nargs="+", help="time-series columns (default: pressure, shear_stress, "
                   "energy_per_particle, contact_number, packing_fraction where present)")
    p = sub.add_parser("compare", help=cmd_compare.__doc__, description=cmd_compare.__doc__ + "\n\n"
                       + comparison.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p.add_argument("--observable", nargs="+", default=["pressure", "shear_stress"],
                   help="time-series columns compared (default: pressure shear_stress; --collapse: the first)")
    p.add_argument("--by", choices=["model", "file"], default="model",
                   help="what a group is: a model (archives read together) or an archive file (each read on its "
                   "own: the same campaign run twice, other settings or code versions)")
    p.add_argument("--model", help="only this model")
    p.add_argument("--N", type=int, help="only this system size (--collapse: the size fitted, default the largest)")
    p.add_argument("--phi", type=float, help="only this packing fraction")
    p.add_argument("--rate", type=float, help="only this shear rate")
    p.add_argument("--alpha", type=float, default=comparison.ALPHA, help="level of the tests (default 0.05)")
    p.add_argument("--outdir", help="write compare.tsv, compare_averages.tsv and compare.png here")
    p.add_argument("--collapse", action="store_true",
                   help="the joint collapse (shared phi_J, q, znu) against separate ones, F test (>= 3 rates)")
    p.add_argument("--degree", type=int, default=3, help="--collapse: degree of ln F(x) (default 3)")
    for name, func in (("collapse", cmd_collapse),):
        p = sub.add_parser(name, help=func.__doc__, description=func.__doc__ + " " + scaling.__doc__)
        _common(p)
        p.add_argument("--degree", type=int, default=3, help="degree of ln F(x) (default 3)")
        if name == "collapse":
            p.add_argument("outdir", help="folder for the tables and figures (made if missing)")
            _window_options(p)
            p.add_argument("--auto-window", action="store_true",
                           help="choose the window from the data (the largest whose fit is acceptable)")
            p.add_argument("--correction", action="store_true", help="leading correction to scaling")
            p.add_argument("--correction-degree", type=int, default=0, help="degree of Q(x) (default 0)")
            p.add_argument("--bootstrap", type=int, default=0, help="resamples of the bootstrap over seeds")
            p.add_argument("--start", type=float, nargs=3, default=[0.843, 0.28, 3.5], metavar=("PHI_J", "Q", "ZNU"),
                           help="starting values of the fit (default 0.843 0.28 3.5)")
    p = sub.add_parser("sizes", help=cmd_sizes.__doc__, description=cmd_sizes.__doc__ + "\n\n" + trends.__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files (two or more sizes)")
    p.add_argument("--observable", default="pressure", choices=["pressure", "shear_stress"],
                   help="the observable fitted (default pressure)")
    p.add_argument("--model", help="only this model (needed when the archives hold several)")
    p.add_argument("outdir", help="folder for the tables and the figure (made if missing)")
    _window_options(p)
    p.add_argument("--degree", type=int, default=3, help="degree of ln F(x) (default 3)")
    p.add_argument("--bootstrap", type=int, default=100, help="resamples of the bootstrap over seeds (0: none)")
    _plateau_option(p)
    for name, func in (("newtonian", cmd_newtonian), ("bagnold", cmd_bagnold)):
        p = sub.add_parser(name, help=func.__doc__, description=func.__doc__ + " " + rheology.__doc__)
        _common(p, size_help="system size (default: the one with the most phi at their plateau)")
        p.add_argument("outdir", help="folder for the tables and figures (made if missing)")
        p.add_argument("--phi-j", type=float, help="phi_J (default: fitted)")
        p.add_argument("--correction", action="store_true", help="factor 1 + c (phi_J - phi)")
        _plateau_option(p)
    p = sub.add_parser("jamming", help=cmd_jamming.__doc__, description=cmd_jamming.__doc__ + " " + jamming.__doc__)
    p.add_argument("archives", nargs="+", help="archives of RAND, COMPRESS, COOL, COOL_COMPRESS or SHEARED campaigns")
    p.add_argument("--correction", action="store_true", help="free shift exponent (1/nu + omega)")
    p = sub.add_parser("correlation", help=cmd_correlation.__doc__,
                       description=cmd_correlation.__doc__ + " " + correlations.__doc__)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p = sub.add_parser("picture", help=cmd_picture.__doc__, description=cmd_picture.__doc__ + " " + pictures.__doc__)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p.add_argument("--replica", type=int, default=0, help="replica id (default 0)")
    p.add_argument("--output", default="configuration.png", help="PNG file to write (default configuration.png)")
    p = sub.add_parser("frames", help=cmd_frames.__doc__, description=cmd_frames.__doc__ + " " + order.__doc__)
    p.add_argument("archives", nargs="+", help="campaign archives, shards or replica files")
    p.add_argument("--replica", type=int, default=0, help="replica id (default 0)")
    p.add_argument("--animation", help="write an animated GIF of the frames here")
    return ap


def analyze_main(argv=None):
    parser = analyze_parser()
    a = parser.parse_args(argv)
    if a.command == "collapse":
        _check_window_options(parser, a)
    _check_numbers(parser, a)
    return run_command(globals()[f"cmd_{a.command}"], a, parser.prog)


def report_main(argv=None):
    # The usage said so explicitly: argparse's own made it "ARCHIVE... OUTDIR [ARCHIVE... OUTDIR ...]",
    # which promised several report folders.
    ap = argparse.ArgumentParser(prog=prog_name("jamsim_report.py"), description=_module_text("report").__doc__,
                                 usage="%(prog)s [options] ARCHIVE [ARCHIVE ...] OUTDIR",
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("paths", nargs="+", metavar="ARCHIVE... OUTDIR",
                    help="campaign archives, shards or replica files, then the report directory")
    ap.add_argument("--degree", type=int, default=3, help="degree of ln F(x) in collapses (default 3)")
    ap.add_argument("--correction", action="store_true", help="leading correction to scaling in the fits")
    ap.add_argument("--bootstrap", type=int, default=100, help="bootstrap resamples over seeds (0: none)")
    ap.add_argument("--N", type=int, help="system size of the fits (default: the largest; the Newtonian "
                    "and Bagnold fits: the size with the most phi at their plateau)")
    ap.add_argument("--phi-min", type=float, default=-math.inf, help="collapse window: smallest phi (default: all)")
    ap.add_argument("--phi-max", type=float, default=math.inf, help="collapse window: largest phi (default: all)")
    ap.add_argument("--rate-max", type=float, default=math.inf, help="collapse window: largest rate (default: all)")
    window = ap.add_mutually_exclusive_group()
    window.add_argument("--auto-window", action="store_true",
                        help="choose each collapse's window from the data (the largest whose fit is acceptable; "
                        "the default when no window is given), shown first, then the fit to every point")
    window.add_argument("--full-window", action="store_true",
                        help="fit every point only (no window chosen from the data)")
    a = ap.parse_args(argv)
    if len(a.paths) < 2:
        ap.error("give at least one archive and the output directory")
    _check_window_options(ap, a)
    _check_numbers(ap, a)

    def run(a):
        from . import report
        output_directory(a.paths[-1], create=False)
        opts = report.ReportOptions(a.degree, a.correction, a.bootstrap, a.N, a.phi_min, a.phi_max, a.rate_max,
                                    not a.full_window)
        rep = report.build_report(a.paths[:-1], a.paths[-1], opts)
        print(f"ran: {'; '.join(rep.ran) or 'none'}")
        for s in rep.skipped:
            print(f"not run: {s['analysis']}: {s['reason']}")
        print(f"{len(rep.fits)} fitted values; report: {os.path.join(a.paths[-1], 'report.html')} and report.md")
        if not rep.ran:
            raise AnalysisError("no analysis could run on this archive (reasons above and in the report)")

    return run_command(run, a, ap.prog)
