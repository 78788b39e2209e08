#!/usr/bin/python3
"""jamsim export and import, end to end (ctest mpi.export_import).

- Exported LAMMPS data and H5MD files read back with Debian's MDAnalysis: positions (lab
  frame), the tilted box, types and diameters equal the archive's final configurations.
- Debian's LAMMPS (lmp) on an exported data file with jamsim's harmonic potential, exact
  (pair_style python, tools/lammps/harmonic_disks.py): its energy per atom, pressure and pxy
  equal jamsim's final rows to the precision LAMMPS prints (one unit in its last printed
  digit); tabulated as in the LAMMPS baseline (pair_style table): within 2e-7.
- Export refusals: a replica that is not done, an unknown id, an existing output, several
  replicas without {id}; exit status 2, one message, nothing written.
- Import: a replica started from an exported RAND state runs bitwise like one started from the
  archive; a sheared state starts with the archive's final energy, pressure and shear stress;
  a campaign starts from a data file; overlapping types, a tilt that is not a simple shear, a
  cell that is not square and another N are refused, nothing written.

usage: check_export.py JAMSIM SOURCE_DIR MPIEXEC WORKDIR
"""
import math
import os
import re
import shutil
import subprocess
import sys
import warnings

import h5py
import numpy as np

warnings.filterwarnings("ignore")
import MDAnalysis as mda  # noqa: E402

JAMSIM, SOURCE, MPIEXEC, WORK = sys.argv[1:5]
CAMPAIGNS = os.path.join(SOURCE, "tests", "data", "campaigns")
STYLE = "id type diameter density x y z"
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(args, expect=0):
    p = subprocess.run(args, capture_output=True, text=True)
    if expect is not None and p.returncode != expect:
        sys.exit(f"FAIL: {' '.join(args)} exited {p.returncode}, expected {expect}\n{p.stdout}\n{p.stderr}")
    return p


def final(archive, r):
    """Final configuration (sheared x, y, diameter), L, gamma and final rows of replica r."""
    with h5py.File(archive, "r", locking=False) as f:
        n = int(f["/replicas/N"][r])
        off = int(f["/replicas/particle_offset"][r])
        out = {k: f["/final/" + k][off:off + n] for k in ("x", "y", "diameter")}
        out["L"] = float(f["/final/box_side"][r])
        out["gamma"] = float(f["/final/box_strain"][r])
        last = int(f["/replicas/n_samples"][r]) - 1
        for k in ("energy_per_particle", "pressure", "shear_stress", "strain"):
            out[k] = float(f["/timeseries/" + k][r, last])
    return out


def printed_unit(text):
    """One unit in the last digit of a number as LAMMPS printed it (%g-style)."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (-decimals + (int(exponent) if exponent else 0))


def no_files(pattern_dir, before):
    return sorted(os.listdir(pattern_dir)) == before


os.makedirs(WORK, exist_ok=True)
os.chdir(WORK)
for name in os.listdir("."):
    shutil.rmtree(name) if os.path.isdir(name) else os.remove(name)
run([MPIEXEC, "-n", "2", JAMSIM, "run", os.path.join(CAMPAIGNS, "export_sheared.toml"), "-o", "sheared.h5"])
run([MPIEXEC, "-n", "2", JAMSIM, "run", os.path.join(CAMPAIGNS, "export_rand.toml"), "-o", "rand.h5"])
run([MPIEXEC, "-n", "1", JAMSIM, "run", os.path.join(CAMPAIGNS, "export_sheared.toml"), "--shard", "0/2",
     "-o", "shard.h5"])

# ---- export: LAMMPS data and H5MD --------------------------------------------------------
out = run([JAMSIM, "export", "sheared.h5", "--replica", "0,1", "-o", "sheared_{id}.data"]).stdout
check("sheared_0.data" in out and "sheared_1.data" in out, "export names the files it wrote")
run([JAMSIM, "export", "sheared.h5", "-r", "0-1", "-o", "sheared_{id}.h5md"])
run([JAMSIM, "export", "rand.h5", "-r", "done", "-o", "rand_0.data"])
run([JAMSIM, "export", "rand.h5", "-r", "0", "--format", "h5md", "-o", "rand_0.h5"])

for archive, r, stem in (("sheared.h5", 0, "sheared_0"), ("sheared.h5", 1, "sheared_1"), ("rand.h5", 0, "rand_0")):
    ref = final(archive, r)
    L, g = ref["L"], ref["gamma"]
    lab = np.column_stack([ref["x"] + g * ref["y"], ref["y"], np.zeros_like(ref["y"])])
    box = np.array([[L, 0, 0], [g * L, L, 0], [0, 0, 1.0]])
    h5md = stem + (".h5" if stem.startswith("rand") else ".h5md")
    u = mda.Universe(stem + ".data", atom_style=STYLE)
    tol = 4e-7 * L  # MDAnalysis keeps float32
    check(u.atoms.n_atoms == len(ref["x"]), f"{stem}.data: MDAnalysis reads {len(ref['x'])} atoms")
    check(np.allclose(u.atoms.positions, lab, atol=tol, rtol=0), f"{stem}.data: MDAnalysis positions = archive lab positions")
    check(np.allclose(u.trajectory.ts.triclinic_dimensions, box, atol=tol, rtol=0),
          f"{stem}.data: MDAnalysis box = (L,0,0), (gamma L, L, 0), gamma = {g:.6g}")
    types = np.where(ref["diameter"] > 1.0, "2", "1")
    check(np.array_equal(u.atoms.types, types), f"{stem}.data: types 1/2 follow the diameters")
    with open(stem + ".data") as f:
        rows = [line.split() for line in f.read().split("Atoms # sphere")[1].splitlines() if line.strip()]
    check(np.array_equal(np.array([float(row[2]) for row in rows]), ref["diameter"]),
          f"{stem}.data: diameter column = archive diameters")

    v = mda.Universe(stem + ".data", h5md, atom_style=STYLE, format="H5MD", convert_units=False)
    ts = v.trajectory.ts
    check(v.trajectory.n_frames == 1, f"{h5md}: one frame")
    check(np.allclose(v.atoms.positions, lab, atol=tol, rtol=0), f"{h5md}: MDAnalysis positions = archive lab positions")
    check(np.allclose(ts.triclinic_dimensions, box, atol=tol, rtol=0), f"{h5md}: MDAnalysis box")
    check(all(ts.data[k] == ref[k] for k in ("energy_per_particle", "pressure", "shear_stress")),
          f"{h5md}: observables = the archive's final row")
    with h5py.File(h5md, "r") as f:
        check(np.array_equal(f["/particles/all/diameter"][:], ref["diameter"]), f"{h5md}: diameters bitwise")
        check(np.array_equal(f["/particles/all/species"][:], (ref["diameter"] > 1.0).astype(int)),
              f"{h5md}: species 0 small, 1 large")
        pos = f["/particles/all/position/value"][0]
        check(np.array_equal(pos[:, 1], ref["y"]) and np.allclose(pos[:, 0], lab[:, 0], atol=1e-14 * L, rtol=0),
              f"{h5md}: float64 positions")
        check(list(f["/h5md"].attrs["version"]) == [1, 1], f"{h5md}: H5MD version 1.1")

# ---- LAMMPS: energy, pressure and shear stress of the exported states --------------------
# Two ways of giving LAMMPS jamsim's potential: exactly (pair_style python with
# tools/lammps/harmonic_disks.py), compared to the precision LAMMPS prints (one unit in its last
# digit); and the table of the LAMMPS baseline (tools/lammps/make_table.py, 100000 points),
# whose linear interpolation errs by up to ~1e-7 of the energy of a barely jammed state.
run(["/usr/bin/python3", os.path.join(SOURCE, "tools", "lammps", "make_table.py"), "harmonic.table", "100000"])
header = "units lj\ndimension 2\natom_style sphere\nboundary p p p\nread_data ${data}\n"
footer = "thermo_style custom step pe press pxy\nrun 0\n"
with open("in.python", "w") as f:
    f.write(header + "pair_style python 1.4\npair_coeff * * harmonic_disks.Harmonic 1.0 1.4\n" + footer)
with open("in.table", "w") as f:
    f.write(header + "pair_style table linear 100000\npair_coeff 1 1 harmonic.table SS\n"
            "pair_coeff 1 2 harmonic.table SL\npair_coeff 2 2 harmonic.table LL\n" + footer)
lammps_env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE, "tools", "lammps"))
for archive, r, stem in (("sheared.h5", 0, "sheared_0"), ("sheared.h5", 1, "sheared_1"), ("rand.h5", 0, "rand_0")):
    ref = final(archive, r)
    check(ref["pressure"] > 1e-3, f"{stem}: a compressed state (p = {ref['pressure']:.3g}), so the check means something")
    for potential in ("python", "table"):
        p = subprocess.run(["lmp", "-in", "in." + potential, "-var", "data", stem + ".data", "-log", "none", "-nocite"],
                           capture_output=True, text=True, env=lammps_env)
        m = re.search(r"Step\s+PotEng\s+Press\s+Pxy\s*\n\s*0\s+(\S+)\s+(\S+)\s+(\S+)", p.stdout)
        if p.returncode != 0 or not m:
            sys.exit(f"FAIL: LAMMPS ({potential}) on {stem}.data:\n{p.stdout}\n{p.stderr}")
        for text, value, name in zip(m.groups(), (ref["energy_per_particle"], ref["pressure"], -ref["shear_stress"]),
                                     ("pe/atom = E/N", "press = p", "pxy = -sigma")):
            allowed = printed_unit(text) if potential == "python" else 2e-7 * abs(value)
            check(abs(float(text) - value) <= allowed,
                  f"{stem}: LAMMPS pair_style {potential} {name}: {text} against jamsim {value:.10g} (within {allowed:.2g})")

# ---- export refusals ---------------------------------------------------------------------
before = sorted(os.listdir("."))
for args, message in (
        (["shard.h5", "-r", "1", "-o", "x.data"],
         "replica 1 of 'shard.h5' is pending: only a done replica has a final configuration"),
        (["sheared.h5", "-r", "7", "-o", "x.data"], "--replica = 7 is not allowed: 'sheared.h5' has replicas 0 to 1"),
        (["sheared.h5", "-r", "0", "-o", "sheared_0.data"],
         "-o = 'sheared_0.data' is not allowed: it exists (jamsim export does not overwrite"),
        (["sheared.h5", "-r", "0,1", "-o", "both.data"], "-o = 'both.data' is not allowed for 2 replicas: a name with {id}"),
        (["sheared.h5", "-r", "0", "--format", "xyz", "-o", "x.xyz"], "--format = xyz is not allowed: lammps or h5md"),
        (["missing.h5", "-r", "0", "-o", "x.data"], "missing.h5"),
        (["sheared.h5", "-r", "0", "-o", "no/such/dir/x.data"], "a file in an existing directory")):
    p = run([JAMSIM, "export"] + args, expect=None)
    check(p.returncode == 2 and message in p.stderr and p.stderr.count("\n") == 1,
          f"export {' '.join(args)}: exit 2, '{message}'" + ("" if p.returncode == 2 else f" (got {p.returncode}: {p.stderr})"))
check(no_files(".", before), "refused exports wrote nothing")

# ---- import: the exported state as a start ------------------------------------------------
common = ["--model", "RD0", "--N", "256", "--phi", "0.86", "--rate", "1e-3", "--strain", "0.02",
          "--sample-interval", "0.01", "--seed", "1"]
run([JAMSIM, "replica"] + common + ["--initial", "rand.h5", "-o", "from_archive.h5"])
run([JAMSIM, "replica"] + common + ["--initial", "rand_0.data", "-o", "from_data.h5"])
with h5py.File("from_archive.h5", "r") as a, h5py.File("from_data.h5", "r") as b:
    same = all(np.array_equal(a["final/" + k][:], b["final/" + k][:]) for k in ("x", "y", "diameter"))
    same = same and all(np.array_equal(a["timeseries/" + k][:], b["timeseries/" + k][:], equal_nan=True)
                        for k in ("energy_per_particle", "pressure", "shear_stress"))
    check(same, "a replica started from rand_0.data runs bitwise like one started from rand.h5")
sheared = final("sheared.h5", 1)
run([JAMSIM, "replica"] + common[:-1] + ["2", "--initial", "sheared_1.data", "-o", "from_sheared.h5"])
with h5py.File("from_sheared.h5", "r") as f:
    for k in ("energy_per_particle", "pressure", "shear_stress"):
        start = float(f["timeseries/" + k][0])
        check(math.isclose(start, sheared[k], rel_tol=1e-12),
              f"sheared_1.data as a start: {k} at step 0 = {start:.17g}, the archive's final {sheared[k]:.17g}")

with open("from_data.toml", "w") as f:
    f.write('[campaign]\nname = "from-data"\noutput = "from-data.h5"\n[run]\ninitial = "rand_0.data"\n'
            'strain = 0.02\nsample_interval = 0.01\n[sweep]\nN = [256]\nphi = [0.86]\nrate = [1e-3]\nseeds = 1\n')
run([MPIEXEC, "-n", "2", JAMSIM, "run", "from_data.toml"])
check("1/1 done" in run([JAMSIM, "status", "from-data.h5"]).stdout, "a campaign with [run] initial = a data file")
with open("wrong_n.toml", "w") as f:
    f.write('[campaign]\nname = "wrong-n"\noutput = "wrong-n.h5"\n[run]\ninitial = "rand_0.data"\n'
            'strain = 0.02\n[sweep]\nN = [128]\nphi = [0.86]\nrate = [1e-3]\nseeds = 1\n')
p = run([JAMSIM, "run", "wrong_n.toml"], expect=None)
check(p.returncode == 2 and "wrong_n.toml: [run] initial = \"rand_0.data\": 'rand_0.data' has 256 atoms: the replica "
      "has N = 128" in p.stderr and not os.path.exists("wrong-n.h5"),
      "a campaign of another N refused before any work: " + p.stderr.strip())

text = open("sheared_0.data").read()
bad = {
    "overlap.data": (re.sub(r"\n1 1 1 1 ", "\n1 1 1.4 1 ", text, count=1),
                     "atom 1 of type 1 has diameter 1.4: type 1 is the small disk"),
    "xz.data": (re.sub(r" 0 0 xy xz yz", " 0.3 0 xy xz yz", text), "a simple shear in the xy plane tilts only xy"),
    "rect.data": (re.sub(r"\n0 (\S+) ylo yhi", "\n0 30 ylo yhi", text), "jamsim's sheared cell is square"),
}
for name, (content, message) in bad.items():
    with open(name, "w") as f:
        f.write(content)
for name, n, message in [(k, "256", m) for k, (_, m) in bad.items()] + [
        ("sheared_0.data", "128", "'sheared_0.data' has 256 atoms: the replica has N = 128")]:
    before = sorted(os.listdir("."))
    args = [a if a != "256" else n for a in common] + ["--initial", name, "-o", "refused.h5"]
    p = run([JAMSIM, "replica"] + args, expect=None)
    check(p.returncode == 2 and message in p.stderr and f"--initial = {name}" in p.stderr and no_files(".", before),
          f"replica --initial {name} (N = {n}) refused: {p.stderr.strip()}")

if failures:
    sys.exit(f"{len(failures)} checks failed")
print("export and import checks passed")
