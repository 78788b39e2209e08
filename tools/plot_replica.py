#!/usr/bin/python3
"""Plot the time series of a jamsim replica file.

usage: tools/plot_replica.py REPLICA.h5 FIGURE.png

Draws pressure, shear stress, energy per particle and contact number against the
accumulated strain, with the post-transient means as dashed lines.
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    path, figure = argv[1], argv[2]
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"plot_replica: cannot open '{path}' as HDF5: {e}")
    with f:
        if "replicas" in f:  # a campaign archive, not a replica file
            sys.exit(f"plot_replica: '{path}' is a campaign archive; plot it with "
                     f"tools/plot_campaign.py {path} OUTDIR")
        if "timeseries" not in f:
            sys.exit(f"plot_replica: '{path}' is not a jamsim replica file (no /timeseries)")
        ts = f["timeseries"]
        a = f.attrs
        strain = ts["strain"][...]
        transient = a.get("transient", 0.0)  # minimisation files without a transient
        panels = [("pressure", "$p$"), ("shear_stress", r"$\sigma$"),
                  ("energy_per_particle", "$E/N$"), ("contact_number", "$z$")]
        fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(6, 8))
        for ax, (name, label) in zip(axes, panels):
            values = ts[name][...]
            ax.plot(strain, values, lw=0.8)
            if name == "energy_per_particle" and (values > 0).all():
                ax.set_yscale("log")  # the start-up transient spans decades
            steady = values[strain >= transient]
            if steady.size:
                ax.axhline(steady.mean(), ls="--", color="k", lw=0.8)
            ax.set_ylabel(f"{label} [{ts[name].attrs['units']}]")
        axes[-1].set_xlabel("strain $\\dot\\gamma t$")
        axes[0].set_title(f"{a['model']}  N={a['N']}  $\\phi$={a['phi']}  "
                          f"$\\dot\\gamma$={a['rate']:g}  seed={a['seed']}")
        fig.tight_layout()
        fig.savefig(figure, dpi=120)
    print(f"figure written to {figure}")


if __name__ == "__main__":
    main(sys.argv)
