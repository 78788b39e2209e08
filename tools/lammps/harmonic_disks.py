"""jamsim's pair potential for LAMMPS `pair_style python`, evaluated exactly (no table).

    V(r) = (k_e/alpha) (1 - r/d_ij)^alpha for r < d_ij, d_ij = (d_i + d_j)/2, k_e = 1, alpha = 2

Usage in a LAMMPS input (this folder on PYTHONPATH; one diameter per atom type):

    pair_style python 1.4
    pair_coeff * * harmonic_disks.Harmonic 1.0 1.4

Debian 12's LAMMPS (29 Sep 2021) has no harmonic/cut; a table (make_table.py) is fast but
carries an interpolation error of order 1e-8 relative in the energy. This class costs a Python
call per pair and is meant for cross-checks of single configurations (jamsim export).
"""
import math


class Harmonic:
    alpha = 2.0

    def __init__(self):
        self.diameter = {}  # LAMMPS atom type -> diameter

    def check_units(self, units):
        if units != "lj":
            raise ValueError(f"harmonic_disks: units lj (reduced), not {units}")

    def map_coeff(self, name, ltype):
        self.diameter[ltype] = float(name)

    def _overlap(self, rsq, itype, jtype):
        d = 0.5 * (self.diameter[itype] + self.diameter[jtype])
        r = math.sqrt(rsq)
        return r, d, (1.0 - r / d if r < d else 0.0)

    def compute_force(self, rsq, itype, jtype):
        """|F|/r: LAMMPS multiplies by the separation vector."""
        r, d, x = self._overlap(rsq, itype, jtype)
        return x ** (self.alpha - 1.0) / d / r if x > 0.0 else 0.0

    def compute_energy(self, rsq, itype, jtype):
        _, _, x = self._overlap(rsq, itype, jtype)
        return x ** self.alpha / self.alpha if x > 0.0 else 0.0
