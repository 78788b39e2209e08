#!/usr/bin/python3
"""Write harmonic.table for LAMMPS 'pair_style table linear N' (LAMMPS in Debian 12 has no
harmonic/cut pair style).

V(r) = ke/2 (1 - r/d_ij)^2 for r < d_ij, sections SS (d = 1.0), SL (1.2), LL (1.4), points
uniform in r^2 (RSQ) so LAMMPS uses them as written; the contact r = d_ij is a grid node and
one zero node lies beyond it, so pairs relaxing onto r = d_ij never leave the table.

usage: make_table.py OUTPUT [N]
"""
import math
import sys

out_path = sys.argv[1]
n = int(sys.argv[2]) if len(sys.argv) > 2 else 100000
with open(out_path, "w") as out:
    out.write(f"# V = 1/2 (1 - r/d)^2, RSQ spacing, N = {n}\n\n")
    for name, d in {"SS": 1.0, "SL": 1.2, "LL": 1.4}.items():
        s_in = (1e-3 * d) ** 2
        ds = (d * d - s_in) / (n - 2)
        r_out = math.sqrt(d * d + ds)
        out.write(f"{name}\nN {n} RSQ {math.sqrt(s_in):.17g} {r_out:.17g}\n\n")
        for i in range(n):
            s = s_in + (r_out * r_out - s_in) * i / (n - 1)
            r = math.sqrt(s) if i < n - 2 else (d if i == n - 2 else r_out)
            x = max(0.0, 1.0 - r / d)
            out.write(f"{i + 1} {r:.17g} {0.5 * x * x:.17g} {x / d:.17g}\n")
        out.write("\n")
