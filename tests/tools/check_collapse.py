"""usage: check_collapse.py REPO_ROOT WORKDIR
The scaling collapse of jamsim's analysis package (`jamsim_analyze.py collapse`, the one
collapse the report also fits) against flow curves with a known answer: an archive (the campaign
layout) whose replica means follow O = rate^q exp(P(x)), x = (phi - phi_J)/rate^(1/znu),
times log-normal noise of 2% per replica, 8 seeds per (phi, rate). The fit must recover
phi_J, q and znu within 3 of its standard errors, with chi2/dof within 5 sigma of its
expectation (n-1)/(n-3) = 1.4 for weights from n = 8 seeds, and bad input must be refused
with a message naming what is wrong."""
import os
import subprocess
import sys

import h5py
import numpy as np

root, work = sys.argv[1:3]
tool = os.path.join(root, "tools", "jamsim_analyze.py")
os.makedirs(work, exist_ok=True)
truth = {"phi_J": 0.8433, "q": 0.28, "znu": 3.5}
coef = [0.5, 2.0, -0.8]  # ln F(x) = 0.5 + 2 x - 0.8 x^2
rng = np.random.default_rng(12345)
phis = np.round(np.linspace(0.825, 0.865, 9), 4)
rates = [1e-3, 3e-4, 1e-4, 3e-5, 1e-5]
seeds = 8
rows = [(phi, rate) for phi in phis for rate in rates for _ in range(seeds)]
m = len(rows)


def write_archive(path, rows):
    with h5py.File(path, "w") as f:
        f.attrs["model"] = "RD0"
        r, ts = f.create_group("replicas"), f.create_group("timeseries")
        r["status"] = np.full(len(rows), 2, dtype=np.int8)
        r["N"] = np.full(len(rows), 1024.0)
        r["phi"] = np.array([p for p, _ in rows])
        r["rate"] = np.array([g for _, g in rows])
        r["seed"] = np.array([float(k % seeds + 1) for k in range(len(rows))])
        r["transient"] = np.full(len(rows), 0.5)
        r["n_samples"] = np.full(len(rows), 2.0)
        x = (r["phi"][...] - truth["phi_J"]) / r["rate"][...] ** (1 / truth["znu"])
        value = r["rate"][...] ** truth["q"] * np.exp(np.polyval(coef[::-1], x))
        value *= np.exp(rng.normal(0.0, 0.02, len(rows)))
        ts["strain"] = np.tile([0.0, 1.0], (len(rows), 1))
        ts["pressure"] = np.stack([np.full(len(rows), 1e9), value], axis=1)  # transient row dropped
        ts["shear_stress"] = ts["pressure"][...]


archive = os.path.join(work, "synthetic.h5")
write_archive(archive, rows)
out = os.path.join(work, "fit")
subprocess.run(["/usr/bin/python3", tool, "collapse", archive, out, "--degree", "2"], check=True)
rows = [line.rstrip("\n").split("\t") for line in open(os.path.join(out, "collapse_pressure.tsv"))][1:]
fit = {k: float(v) for k, v, _ in rows} | {k + "_error": float(e) for k, _, e in rows if e}
assert fit["points"] == len(phis) * len(rates), fit["points"]
for name, value in truth.items():
    assert abs(fit[name] - value) <= 3 * fit[name + "_error"], (name, fit[name], fit[name + "_error"], value)
dof = fit["points"] - (3 + 3)
expected = (seeds - 1) / (seeds - 3)  # E[sigma^2/s^2] for a variance estimated from n samples
assert abs(fit["chi2_per_dof"] - expected) <= 5 * expected * np.sqrt(2 / dof), fit["chi2_per_dof"]
assert os.path.getsize(os.path.join(out, "collapse_pressure.png")) > 0

# Bad input: a missing archive, a size not in the archive, too few points for the fit.
bad = subprocess.run(["/usr/bin/python3", tool, "collapse", os.path.join(work, "missing.h5"), out],
                     capture_output=True, text=True)
assert bad.returncode == 2 and "missing.h5" in bad.stderr, bad.stderr
bad = subprocess.run(["/usr/bin/python3", tool, "collapse", archive, out, "--N", "64"], capture_output=True,
                     text=True)
assert bad.returncode == 2 and "N = 64" in bad.stderr and "1024" in bad.stderr, bad.stderr
bad = subprocess.run(["/usr/bin/python3", tool, "collapse", archive, out, "--phi-max", "0.826"], capture_output=True,
                     text=True)
assert bad.returncode == 2 and "points" in bad.stderr, bad.stderr
print("collapse: phi_J %.5f +- %.5f, q %.4f +- %.4f, znu %.3f +- %.3f, chi2/dof %.2f (truth 0.8433, 0.28, 3.5)"
      % (fit["phi_J"], fit["phi_J_error"], fit["q"], fit["q_error"], fit["znu"], fit["znu_error"], fit["chi2_per_dof"]))
