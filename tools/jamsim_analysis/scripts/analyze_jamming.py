"""Static analysis of jamsim jamming campaigns (RAND, COOL, COMPRESS, COOL_COMPRESS, SHEARED).

usage: analyze_jamming.py ARCHIVE [ARCHIVE ...] OUTDIR

ARCHIVE: campaign archives, shards of one campaign or several campaigns of one model read
together (shards merged; a replica held by several archives, e.g. a campaign and its grown
or merged version, counted once). Finished replicas only. OUTDIR: the output directory
(created if needed). Prints the tables as well. A thin command over tools/jamsim_analysis
(jamming.py); `jamsim_analyze.py jamming` adds the thresholds per N and their finite-size
scaling.

RAND, COOL (one quenched state at the replica's phi):
  pj.tsv, pj.png, and the printed table, one row per (N, phi):
    N               number of disks
    phi             packing fraction of the quench
    configurations  finished replicas (seeds) at (N, phi)
    P_J             fraction of them jammed (`jammed` = 1: the minimiser stopped with the
                    forces balanced, not below energy_floor)
    error           binomial standard error sqrt(max(P_J (1 - P_J), (1/m)(1 - 1/m)) / m),
                    m = configurations (never 0, even at P_J = 0 or 1)
    mean_p_jammed   mean pressure p of the jammed states (k_e/d_s^2; nan if none)
    mean_Z_jammed   mean contact number of their non-rattlers, Z = 2 N_c' / N' (nan if none)
  pressure.png: the distribution of p of the jammed states at each (N, phi) with >= 5.

COMPRESS, COOL_COMPRESS, SHEARED (one jammed state at the configuration's own phi_J):
  phi_j.tsv, phi_j.png (histograms), and the printed table, one row per N:
    N                   number of disks
    configurations      jammed states (finished replicas with jammed = 1)
    mean_phi_J          mean of their packing_fraction (phi_J, from above within phi_tol)
    std_phi_J           sample standard deviation of phi_J (n - 1; nan for one state)
    isostatic_fraction  fraction of the states that are isostatic: after removing rattlers
                        (disks with fewer than 3 contacts, repeatedly) the N' remaining disks
                        have exactly N_c' = 2(N' - 1) + 1 contacts, i.e. excess_contacts = 0,
                        with no tolerance. This is z = 2 N_c'/N' = 2d = 4 in two dimensions
                        up to its finite-size correction (2 per disk, less 2 for the global
                        translations, plus 1 for a positive pressure in a fixed box).
  pj_from_phi_j.tsv, .png: P_J(phi) as the cumulative distribution of phi_J (a configuration
    compressed to phi jams iff phi >= its phi_J): N, phi (each phi_J), P_J (fraction with
    phi_J <= phi), error (binomial standard error).
  phi_J depends on the start phi of the search (campaigns/models.md, "Which start phi for
  COMPRESS"): a note is printed when one N mixes several start phi."""
import argparse
import os
import sys

# numpy, matplotlib (Agg) and the analysis modules are imported where they are used, so that
# --help and argument errors do not wait for them.
from .. import AnalysisError
from ..command_support import output_directory, prog_name, pyplot, run_script


def analyze(a):
    import numpy as np
    from .. import jamming, open_archives
    paths, out = a.archives, a.outdir
    names = ", ".join(paths)
    run = open_archives(paths)
    if "jammed" not in run.observables():
        raise AnalysisError(f"{names} has no /timeseries/jammed: not a jamsim archive of this version")
    models = run.models
    if len(models) > 1:
        raise AnalysisError(f"{names} hold models {', '.join(models)}: analyse one model at a time")
    name = models[0]
    if name in jamming.COMPRESSED:
        model = "COMPRESS"  # one state at phi_J+ per replica
    elif name in jamming.QUENCHED:
        model = "RAND"  # one quenched state at phi per replica
    else:
        raise AnalysisError(f"{names}: model '{name}' is not allowed: RAND, COOL, COMPRESS, COOL_COMPRESS "
                            "or SHEARED (flow campaigns: plot_campaign.py, jamsim_analyze.py collapse)")
    states = jamming.static_states(run)  # finished replicas, the state's columns
    output_directory(out)
    plt = pyplot()
    N = states["N"].to_numpy().astype(int)
    phi = states["phi"].to_numpy()
    jammed = states["jammed"].to_numpy()
    p = states["pressure"].to_numpy()
    z = states["contact_number_nonrattler"].to_numpy()
    phi_state = states["packing_fraction"].to_numpy()
    excess = states["excess_contacts"].to_numpy()
    if model == "RAND":
        rows = []
        fig, ax = plt.subplots(figsize=(5, 4))
        for n in sorted(set(N)):
            phis = sorted(set(phi[N == n]))
            pj, err = [], []
            for ph in phis:
                sel = (N == n) & (phi == ph)
                k, m = jammed[sel].sum(), sel.sum()
                q = k / m
                pj.append(q)
                err.append(np.sqrt(max(q * (1 - q), (1 / m) * (1 - 1 / m)) / m))
                zs = z[sel & (jammed == 1)]
                rows.append((n, ph, m, q, err[-1], np.mean(p[sel & (jammed == 1)]) if k else np.nan,
                             np.mean(zs) if k else np.nan))
            ax.errorbar(phis, pj, yerr=err, marker="o", capsize=2, label=f"N = {n}")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(r"$P_J$")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pj.png"), dpi=120)
        with open(os.path.join(out, "pj.tsv"), "w") as t:
            t.write("N\tphi\tconfigurations\tP_J\terror\tmean_p_jammed\tmean_Z_jammed\n")
            for row in rows:
                t.write("\t".join(str(v) for v in row) + "\n")
        print("N     phi     configs  P_J    error  <p>_jammed  <Z>_jammed")
        for n, ph, m, q, e, mp, mz in rows:
            print(f"{n:<5d} {ph:<7.4f} {m:<8d} {q:<6.3f} {e:<6.3f} {mp:<11.4g} {mz:.4f}")
        fig, ax = plt.subplots(figsize=(5, 4))
        for n in sorted(set(N)):
            for ph in sorted(set(phi[N == n])):
                sel = (N == n) & (phi == ph) & (jammed == 1)
                if sel.sum() >= 5:
                    ax.hist(p[sel], bins=15, histtype="step", density=True, label=f"N={n}, phi={ph}")
        ax.set_xlabel("p (jammed states)")
        ax.set_ylabel("probability density")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pressure.png"), dpi=120)
    else:
        ok = jammed == 1
        fig, ax = plt.subplots(figsize=(5, 4))
        print("N     configs  <phi_J>    std(phi_J)  isostatic (fraction with excess_contacts = 0)")
        with open(os.path.join(out, "phi_j.tsv"), "w") as t:
            t.write("N\tconfigurations\tmean_phi_J\tstd_phi_J\tisostatic_fraction\n")
            for n in sorted(set(N)):
                sel = (N == n) & ok
                v = phi_state[sel]
                iso = np.mean(excess[sel] == 0) if sel.any() else np.nan
                sd = np.std(v, ddof=1) if len(v) > 1 else np.nan
                t.write(f"{n}\t{len(v)}\t{np.mean(v)}\t{sd}\t{iso}\n")
                print(f"{n:<5d} {len(v):<8d} {np.mean(v):<10.6f} {sd:<11.6f} {iso:.3f}")
                ax.hist(v, bins=12, histtype="step", density=True, label=f"N = {n}")
        ax.set_xlabel(r"$\phi_J$")
        ax.set_ylabel("probability density")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, "phi_j.png"), dpi=120)
        # P_J(phi) of this protocol: a configuration compressed to phi jams iff phi >= its
        # phi_J, so P_J is the cumulative distribution of phi_J (with binomial errors).
        fig, ax = plt.subplots(figsize=(5, 4))
        with open(os.path.join(out, "pj_from_phi_j.tsv"), "w") as t:
            t.write("N\tphi\tP_J\terror\n")
            for n in sorted(set(N)):
                v = np.sort(phi_state[(N == n) & ok])
                if len(v) == 0:
                    continue
                q = np.arange(1, len(v) + 1) / len(v)
                err = np.sqrt(q * (1 - q) / len(v))
                for x, y, e in zip(v, q, err):
                    t.write(f"{n}\t{x}\t{y}\t{e}\n")
                ax.step(v, q, where="post", label=f"N = {n}")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(r"$P_J(\phi)$ = fraction with $\phi_J \leq \phi$")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pj_from_phi_j.png"), dpi=120)
    if model == "COMPRESS":
        for n in sorted(set(N)):
            starts = sorted(set(phi[N == n]))
            if len(starts) > 1:
                print(f"note: N = {n} mixes start phi {', '.join(f'{v:g}' for v in starts)}; "
                      "phi_J depends on the start")
    print(f"figures and tables in {out}/")


def parser():
    ap = argparse.ArgumentParser(prog=prog_name("analyze_jamming.py"), description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 2)[2],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("archives", nargs="+", metavar="ARCHIVE",
                    help="campaign archives or shards of one jamming model (read together)")
    ap.add_argument("outdir", metavar="OUTDIR", help="output directory (created if needed)")
    return ap


def main(argv=None):
    """The command line (exit status: 0, or 2 on bad input)."""
    return run_script(prog_name("analyze_jamming.py"), analyze, parser().parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
