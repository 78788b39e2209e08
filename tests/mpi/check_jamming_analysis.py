"""usage: check_jamming_analysis.py REPO_ROOT RAND.h5 COMPRESS.h5 OUTDIR
Runs tools/analyze_jamming.py on a RAND and a COMPRESS archive and checks its tables against
an independent reading of the archives: P_J(N, phi) = fraction of jammed replicas, the mean
and spread of phi_J, the isostatic fraction, and P_J(phi) from the phi_J distribution; the
figures must exist. A bad archive path must fail with a message naming it."""
import os
import subprocess
import sys

import h5py
import numpy as np

root, rand_path, compress_path, out = sys.argv[1:5]
tool = os.path.join(root, "tools", "analyze_jamming.py")


def analyze(archive, outdir):
    subprocess.run(["/usr/bin/python3", tool, archive, outdir], check=True, stdout=subprocess.DEVNULL)


def table(path):
    with open(path) as f:
        head = f.readline().rstrip("\n").split("\t")
        return head, [line.rstrip("\n").split("\t") for line in f if line.strip()]


analyze(rand_path, os.path.join(out, "rand"))
head, rows = table(os.path.join(out, "rand", "pj.tsv"))
with h5py.File(rand_path, "r") as f:
    N, phi = f["replicas/N"][...].astype(int), f["replicas/phi"][...]
    jammed = f["timeseries/jammed"][:, 0]
expected = {(n, ph): jammed[(N == n) & (phi == ph)].mean() for n, ph in set(zip(N, phi))}
assert len(rows) == len(expected), (rows, expected)
for row in rows:
    n, ph, m, pj = int(row[0]), float(row[1]), int(row[2]), float(row[3])
    assert m == ((N == n) & (phi == ph)).sum()
    assert abs(pj - expected[(n, ph)]) < 1e-12, (row, expected[(n, ph)])
for name in ("pj.png", "pressure.png"):
    assert os.path.getsize(os.path.join(out, "rand", name)) > 0, name

analyze(compress_path, os.path.join(out, "compress"))
head, rows = table(os.path.join(out, "compress", "phi_j.tsv"))
with h5py.File(compress_path, "r") as f:
    N = f["replicas/N"][...].astype(int)
    phi_j = f["timeseries/packing_fraction"][:, 0]
    excess = f["timeseries/excess_contacts"][:, 0]
for row in rows:
    n = int(row[0])
    v = phi_j[N == n]
    assert int(row[1]) == len(v)
    assert abs(float(row[2]) - v.mean()) < 1e-12
    assert abs(float(row[3]) - v.std(ddof=1)) < 1e-12
    assert abs(float(row[4]) - np.mean(excess[N == n] == 0)) < 1e-12
head, rows = table(os.path.join(out, "compress", "pj_from_phi_j.tsv"))
for row in rows:  # P_J(phi) at each phi_J = fraction of configurations with phi_J <= phi
    n, x, q = int(row[0]), float(row[1]), float(row[2])
    assert abs(q - np.mean(phi_j[N == n] <= x)) < 1e-12, row
for name in ("phi_j.png", "pj_from_phi_j.png"):
    assert os.path.getsize(os.path.join(out, "compress", name)) > 0, name

bad = subprocess.run(["/usr/bin/python3", tool, os.path.join(out, "missing.h5"), out],
                     capture_output=True, text=True)
assert bad.returncode != 0 and "missing.h5" in bad.stderr, (bad.returncode, bad.stderr)
print("analyze_jamming: tables agree with the archives")
