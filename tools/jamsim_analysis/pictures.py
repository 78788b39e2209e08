"""Final configurations: the contact network and its forces, rattlers, and the picture of
the sheared cell in the lab frame (disks to scale, coloured by size; contact forces as lines
of width proportional to the force; rattlers marked).

Forces: V(r) = k_e/alpha (1 - r/d)^alpha for r < d (d = (d_i + d_j)/2), so the contact
force is f = -dV/dr = (k_e/d) (1 - r/d)^(alpha - 1) (units k_e/d_s, k_e = 1).
Lees-Edwards: sheared coordinates (x, y) are periodic in the L x L square; the lab
separation of images is (dx + gamma dy, dy) with dx, dy the sheared separations.
"""
import dataclasses

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402
from .errors import AnalysisError  # noqa: E402

# Rows of the pair search handled at once (memory ~ CHUNK * N doubles per array).
CHUNK = 512
# Disks with fewer contacts are rattlers (d + 1 in d = 2 dimensions), removed repeatedly.
MIN_CONTACTS = 3


@dataclasses.dataclass
class ContactNetwork:
    """Contacts of a configuration: i, j [C] (i < j); dx, dy [C]: lab-frame separation
    r_i - r_j of the touching images (d_s); r [C] its length; force [C] (k_e/d_s, > 0)."""
    i: np.ndarray
    j: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    r: np.ndarray
    force: np.ndarray

    def stress(self, box_side):
        """(pressure, shear stress) of the network: p = (1/2A) sum r.f, sigma = -(1/A) sum
        r_x f_y with f the force on i from j (repulsive: along r_i - r_j)."""
        area = box_side ** 2
        fx, fy = self.force * self.dx / self.r, self.force * self.dy / self.r
        return float(np.sum(self.dx * fx + self.dy * fy) / (2 * area)), float(-np.sum(self.dx * fy) / area)


def lab_separation(dx, dy, box_side, box_strain):
    """Lab-frame minimum-image separation for sheared separations dx, dy (d_s)."""
    L = box_side
    dy = dy - L * np.round(dy / L)
    dx = dx - L * np.round(dx / L)
    lab = dx + box_strain * dy
    lab = lab - L * np.round(lab / L)  # the nearest image along x after the shift
    return lab, dy


def contact_network(final, alpha=2.0):
    """ContactNetwork of a FinalConfiguration (O(N^2) search in chunks of rows)."""
    x, y, d = (np.asarray(a, float) for a in (final.x, final.y, final.diameter))
    n = len(x)
    parts = []
    for start in range(0, n, CHUNK):
        rows = np.arange(start, min(start + CHUNK, n))
        dx, dy = lab_separation(x[rows, None] - x[None, :], y[rows, None] - y[None, :],
                                final.box_side, final.box_strain)
        r = np.hypot(dx, dy)
        reach = 0.5 * (d[rows, None] + d[None, :])
        touching = (r < reach) & (rows[:, None] < np.arange(n)[None, :])
        ii, jj = np.nonzero(touching)
        parts.append((rows[ii], jj, dx[ii, jj], dy[ii, jj], r[ii, jj], reach[ii, jj]))
    i, j, dx, dy, r, reach = (np.concatenate([p[k] for p in parts]) for k in range(6))
    force = (1.0 / reach) * (1 - r / reach) ** (alpha - 1)
    return ContactNetwork(i.astype(int), j.astype(int), dx, dy, r, force)


def rattlers(n, network, min_contacts=MIN_CONTACTS):
    """Boolean mask [n]: disks left with fewer than min_contacts contacts after removing such
    disks repeatedly (their contacts go with them)."""
    active = np.ones(n, bool)
    while True:
        alive = active[network.i] & active[network.j]
        z = np.bincount(network.i[alive], minlength=n) + np.bincount(network.j[alive], minlength=n)
        remove = active & (z < min_contacts)
        if not remove.any():
            return ~active
        active &= ~remove


def strain_text(strain, box_strain):
    """'strain 2, Lees-Edwards offset +0.000' (the accumulated strain and the wrapped box
    offset gamma in [-1/2, 1/2) the picture is drawn with), or only the offset when the
    accumulated strain is unknown (NaN, None)."""
    offset = f"Lees-Edwards offset {box_strain:+.3f}"
    if strain is None or not np.isfinite(strain):
        return offset
    return f"strain {strain:.4g}, {offset}"


def draw_configuration(final, path, alpha=2.0, title="", max_width=4.0, strain=None, caption=""):
    """PNG of a configuration in the lab frame of the sheared cell: disks to scale (small
    blue, large orange), images of disks crossing the parallelogram's edges, contact
    forces as black lines of width proportional to the force (max_width points for the
    largest), rattlers grey with a red cross, the cell's parallelogram in green; a legend
    below the cell says so. strain: the accumulated strain of the configuration (the
    archive's, Archive.final_strain; the box offset final.box_strain is only its wrapped
    part); the default title names it, N, the contacts and rattlers; caption: a first
    title line (e.g. the replica's parameters). Returns (network, rattler mask)."""
    L, gamma = final.box_side, final.box_strain
    net = contact_network(final, alpha)
    rattler = rattlers(len(final.x), net)
    lab_x, y, d = final.lab_x(), np.asarray(final.y), np.asarray(final.diameter)
    small = d <= np.median(d) if np.ptp(d) > 0 else np.ones(len(d), bool)
    fig, ax = plt.subplots(figsize=(6, 6))
    patches, colours = [], []
    for sx in (-1, 0, 1):
        for sy in (-1, 0, 1):
            cx, cy = lab_x + sx * L + sy * gamma * L, y + sy * L
            near = (cy > -d) & (cy < L + d) & (cx - gamma * cy > -d) & (cx - gamma * cy < L + d)
            for k in np.flatnonzero(near):
                patches.append(Circle((cx[k], cy[k]), d[k] / 2))
                colours.append("0.75" if rattler[k] else ("tab:blue" if small[k] else "tab:orange"))
    ax.add_collection(PatchCollection(patches, facecolors=colours, edgecolors="k", linewidths=0.3, alpha=0.8))
    if len(net.force):
        start = np.column_stack([lab_x[net.i], y[net.i]])
        end = start - np.column_stack([net.dx, net.dy])
        widths = max_width * net.force / net.force.max()
        ax.add_collection(LineCollection(np.stack([start, end], axis=1), linewidths=widths, colors="k"))
    ax.plot(lab_x[rattler], y[rattler], "x", color="r", ms=4)
    corners = [(0, 0), (L, 0), (L + gamma * L, L), (gamma * L, L)]
    ax.add_patch(Polygon(corners, closed=True, fill=False, ec="g", lw=1))
    ax.set_aspect("equal")
    ax.set_xlim(min(0, gamma * L) - 1, max(L, L + gamma * L) + 1)
    ax.set_ylim(-1, L + 1)
    ax.set_xlabel(r"lab $x$ ($d_s$)")
    ax.set_ylabel(r"$y$ ($d_s$)")
    ax.set_title(title or ((caption + "\n") if caption else "") + f"N = {len(d)}, {strain_text(strain, gamma)}, "
                 f"{len(net.force)} contacts, {int(rattler.sum())} rattlers", fontsize=9)
    ax.legend(handles=legend_handles(d, small, net, max_width), loc="upper center", bbox_to_anchor=(0.5, -0.1),
              ncol=3, fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return net, rattler


def legend_handles(diameter, small, network, max_width):
    """Proxy artists of the picture's legend: the disk colours (with their diameters), the
    rattler mark, the force lines (width of the largest force) and the cell."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    d = np.asarray(diameter, float)
    sizes = sorted(set(np.round(d, 6)))
    if len(sizes) <= 2:
        names = ([f"small disk (d = {d[small].min():g})", f"large disk (d = {d[~small].max():g})"]
                 if (~small).any() else [f"disk (d = {d.min():g})", None])
    else:
        names = [f"smaller half (d <= {np.median(d):.3g})", f"larger half (d > {np.median(d):.3g})"]
    handles = [Patch(fc="tab:blue", ec="k", lw=0.3, alpha=0.8, label=names[0])]
    if names[1]:
        handles.append(Patch(fc="tab:orange", ec="k", lw=0.3, alpha=0.8, label=names[1]))
    handles.append(Line2D([], [], marker="x", color="r", mfc="0.75", ls="none", ms=5,
                          label=f"rattler (< {MIN_CONTACTS} contacts, grey disk)"))
    if len(network.force):
        handles.append(Line2D([], [], color="k", lw=max_width,
                              label=f"contact force (width ∝ f, max {network.force.max():.3g})"))
    handles.append(Patch(fill=False, ec="g", lw=1, label="sheared cell"))
    return handles


def animate_frames(archive, replica, path, alpha=2.0, max_frames=120, seconds_per_frame=0.2):
    """Animated GIF of a replica's configuration frames ([run] frame_interval) in the lab
    frame, each drawn as draw_configuration draws one (contact forces, rattlers); at most
    max_frames, evenly spaced. Returns the number of frames drawn."""
    import os
    import tempfile

    from PIL import Image

    strains, configurations = archive.frames(replica)
    if len(configurations) == 0:
        raise AnalysisError(f"replica {replica} has no configuration frames yet")
    chosen = np.unique(np.linspace(0, len(configurations) - 1, min(max_frames, len(configurations))).round().astype(int))
    with tempfile.TemporaryDirectory() as tmp:
        names = []
        for k in chosen:
            name = os.path.join(tmp, f"frame_{k:05d}.png")
            draw_configuration(configurations[k], name, alpha=alpha, strain=strains[k],
                               caption=f"replica {replica}")
            names.append(name)
        images = [Image.open(n).convert("P", palette=Image.ADAPTIVE) for n in names]
        images[0].save(path, save_all=True, append_images=images[1:], loop=0,
                       duration=int(1000 * seconds_per_frame))
    return len(chosen)
