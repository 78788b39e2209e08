"""Per-replica reads of a jamsim archive for the tests (layout 4: final configurations end to
end from /replicas/particle_offset; layout 3: one NaN-padded row per replica)."""


def final(f, name, k):
    """Replica k's /final/<name> (x, y or diameter), its N values."""
    d = f["final"][name]
    if d.ndim == 2:
        n = int(f["replicas/N"][k])
        return d[k, :n]
    first = int(f["replicas/particle_offset"][k])
    return d[first:first + int(f["replicas/N"][k])]


def replica_row(f, group, name, k):
    """Replica k's entry of any dataset in /timeseries, /final or /correlation."""
    if group == "final" and name in ("x", "y", "diameter"):
        return final(f, name, k)
    return f[group][name][k]
