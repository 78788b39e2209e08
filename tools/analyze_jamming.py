#!/usr/bin/python3
"""usage: analyze_jamming.py ARCHIVE.h5 OUTDIR

Static analysis of a RAND, COOL, COMPRESS, COOL_COMPRESS or SHEARED campaign archive; finished
replicas only.
  RAND, COOL:         P_J(phi, N) with binomial errors, and <p> and <Z> of the jammed states
                      (pj.png, pj.tsv); the pressure distribution of the jammed states at
                      each (phi, N) (pressure.png).
  COMPRESS, COOL_COMPRESS, SHEARED:
                      the distribution of phi_J per N: mean, standard deviation, histogram
                      (phi_j.png, phi_j.tsv), the fraction of isostatic states (states whose
                      non-rattlers have exactly 2(N' - 1) + 1 contacts, excess_contacts = 0),
                      and P_J(phi) as its cumulative distribution (pj_from_phi_j.png, .tsv).
Prints the tables as well. A thin command over tools/jamsim_analysis (jamming.py);
`jamsim_analyze.py jamming` adds the thresholds per N and their finite-size scaling."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from jamsim_analysis import AnalysisError, open_archives  # noqa: E402
from jamsim_analysis import jamming  # noqa: E402


def fail(msg):
    sys.stderr.write(f"analyze_jamming.py: {msg}\n")
    sys.exit(2)


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    if len(sys.argv) != 3:
        fail("usage: analyze_jamming.py ARCHIVE.h5 OUTDIR (--help: what it computes)")
    path, out = sys.argv[1], sys.argv[2]
    try:
        run = open_archives(path)
    except AnalysisError as e:
        fail(f"cannot open archive '{path}': {e}")
    if "jammed" not in run.observables():
        fail(f"'{path}' has no /timeseries/jammed: not a jamsim archive of this version")
    name = run.attributes().get("model", "")
    if name in ("COMPRESS", "COOL_COMPRESS", "SHEARED"):
        model = "COMPRESS"  # one state at phi_J+ per replica
    elif name in ("RAND", "COOL"):
        model = "RAND"  # one quenched state at phi per replica
    else:
        fail(f"'{path}': model '{name}' is not RAND, COOL, COMPRESS, COOL_COMPRESS or SHEARED"
             " (QS: use plot_campaign.py)")
    try:
        states = jamming.static_states(run)  # finished replicas, the state's columns
    except AnalysisError as e:
        fail(f"'{path}': {e}")
    N = states["N"].to_numpy().astype(int)
    phi = states["phi"].to_numpy()
    jammed = states["jammed"].to_numpy()
    p = states["pressure"].to_numpy()
    z = states["contact_number_nonrattler"].to_numpy()
    phi_state = states["packing_fraction"].to_numpy()
    excess = states["excess_contacts"].to_numpy()
    os.makedirs(out, exist_ok=True)
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
    print(f"figures and tables in {out}/")


if __name__ == "__main__":
    main()
