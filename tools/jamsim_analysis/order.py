"""Bond-orientational order psi_6 of 2D configurations (crystallisation under shear, thesis
Figs. 4.6-4.7).

For disk i with neighbours j (Delaunay neighbours of the disk centres in the lab frame, with
the periodic Lees-Edwards images, so that the cell has no edge):
    psi6_i = (1/n_i) sum_j exp(6 i theta_ij),   theta_ij the angle of r_j - r_i.
Two numbers per configuration:
    global  |(1/N) sum_i psi6_i|: 1 for one perfect triangular crystal, ~N^-1/2 for a liquid;
    local   (1/N) sum_i |psi6_i|: hexagonal order around each disk whatever the grains'
            orientations (a polycrystal is high here, low in `global`).
Delaunay neighbours make the definition free of a cutoff; in a triangular lattice every
disk has its 6 nearest neighbours (psi6 = 1), in a square lattice the Delaunay triangulation
adds one diagonal per square (|psi6_i| small, the mean of the global sum near 0).
"""
import numpy as np
import pandas as pd
from scipy.spatial import Delaunay

from .errors import AnalysisError


def _with_images(lab_x, y, box_side, box_strain):
    """Centres [9N, 2] of the disks and their 8 nearest periodic images (lab frame)."""
    L, g = box_side, box_strain
    parts = [np.column_stack([lab_x + sx * L + sy * g * L, y + sy * L]) for sy in (0, -1, 1) for sx in (0, -1, 1)]
    return np.vstack(parts)


def psi6_per_disk(lab_x, y, box_side, box_strain):
    """psi6_i [N] (complex) of the disks at lab positions (lab_x, y) [N] (d_s) in a sheared
    periodic cell of side box_side (d_s) and Lees-Edwards strain box_strain."""
    lab_x, y = np.asarray(lab_x, float), np.asarray(y, float)
    n = len(lab_x)
    if n < 3:
        raise AnalysisError(f"psi6 needs at least 3 disks, got {n}")
    points = _with_images(lab_x, y, box_side, box_strain)
    tri = Delaunay(points)
    indptr, indices = tri.vertex_neighbor_vertices
    # The originals are the first N points: their neighbours are indices[indptr[0]:indptr[n]].
    counts = np.diff(indptr[: n + 1])
    owner = np.repeat(np.arange(n), counts)
    d = points[indices[indptr[0]:indptr[n]]] - points[owner]
    bond = np.exp(6j * np.arctan2(d[:, 1], d[:, 0]))
    total = np.bincount(owner, weights=bond.real, minlength=n) + 1j * np.bincount(owner, weights=bond.imag, minlength=n)
    return total / counts


def psi6(configuration):
    """(global, local) psi6 of a FinalConfiguration (see the module's docstring)."""
    psi = psi6_per_disk(configuration.lab_x(), configuration.y, configuration.box_side,
                        configuration.box_strain)
    return float(abs(psi.mean())), float(np.abs(psi).mean())


def psi6_over_strain(archive, replica):
    """DataFrame of a replica's frames: strain (time at rate 0), psi6_global, psi6_local."""
    strains, configurations = archive.frames(replica)
    rows = [(s, *psi6(c)) for s, c in zip(strains, configurations)]
    return pd.DataFrame(rows, columns=["strain", "psi6_global", "psi6_local"])


def order_by_size_ratio(archive):
    """psi6 over strain for every finished replica with frames, and the late-strain averages.

    Returns (series, summary): series in long form (replica, size_ratio, N, phi, rate, seed,
    strain, psi6_global, psi6_local); summary one row per size ratio: replicas, frames after
    the transient, mean of each replica's late-strain (strain >= its transient) psi6_global
    and psi6_local, and the standard error of that mean over replicas (independent seeds)."""
    done = archive.done()
    with_frames = [int(r) for r in done["replica"] if archive.has_frames(int(r))]
    if not with_frames:
        raise AnalysisError("no finished replica keeps configuration frames (set [run] frame_interval)")
    parts, late = [], []
    for r in with_frames:
        row = archive.replicas.iloc[r]
        s = psi6_over_strain(archive, r)
        for key in ("size_ratio", "N", "phi", "rate", "seed"):
            s[key] = row.get(key, np.nan)
        s.insert(0, "replica", r)
        parts.append(s)
        transient = float(row.get("transient", 0.0)) if np.isfinite(row.get("transient", np.nan)) else 0.0
        tail = s[s["strain"] >= transient]
        if len(tail):
            late.append(dict(size_ratio=row.get("size_ratio", np.nan), frames=len(tail),
                             psi6_global=tail["psi6_global"].mean(), psi6_local=tail["psi6_local"].mean()))
    series = pd.concat(parts, ignore_index=True)
    if not late:
        raise AnalysisError("no frame after the transient in any replica")
    per = pd.DataFrame(late)
    rows = []
    for ratio, g in per.groupby("size_ratio"):
        k = len(g)
        row = dict(size_ratio=ratio, replicas=k, frames=int(g["frames"].sum()))
        for c in ("psi6_global", "psi6_local"):
            row[c] = g[c].mean()
            row[c + "_error"] = g[c].std(ddof=1) / np.sqrt(k) if k > 1 else np.nan
        rows.append(row)
    return series, pd.DataFrame(rows)
