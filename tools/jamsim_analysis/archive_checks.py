"""The checks a campaign archive or single-replica file must pass before the readers of
archive.py rely on its shapes and attributes: a hand-edited or damaged file is refused in words
(AnalysisError naming the file and what is wrong), never met half-way by a traceback."""
import h5py
import numpy as np

from .errors import AnalysisError

STATUS_NAMES = {0: "pending", 1: "running", 2: "done", 3: "failed"}
DONE = 2


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


# The newest campaign archive layout this package reads (kArchiveLayoutVersion in
# include/jamsim/archive/archive_file_check.hpp).
NEWEST_LAYOUT = 4
# /replicas columns every campaign archive has (rate only where a model shears).
REQUIRED_COLUMNS = ("status", "n_samples", "N", "phi", "seed")
# Root attributes of a campaign archive that are text, and those that are one integer.
TEXT_ATTRIBUTES = ("campaign", "model", "spec_text", "spec_path", "spec_fingerprint", "code_version", "build_flags",
                   "created", "run_started", "run_finished", "merged", "extended", "grown")
INTEGER_ATTRIBUTES = ("layout_version", "n_replicas", "n_ranks")
# Root attributes every single-replica file has.
REQUIRED_ATTRIBUTES = ("model", "N", "phi", "seed")


def _damaged(path, what):
    return AnalysisError(f"'{path}' is damaged: {what} (not as jamsim writes it; a hand-edited or "
                         "truncated file?)")


def _root_attributes(path, f):
    """The root's attributes, text decoded; a text attribute that is not text, or not UTF-8, and
    a count that is not one integer are refused in words (they ended in a TypeError or a
    UnicodeDecodeError)."""
    out = {}
    for key, value in f.attrs.items():
        if isinstance(value, (bytes, str)):
            try:
                value = _text(value)
            except UnicodeDecodeError:
                raise _damaged(path, f"its attribute {key} is not UTF-8 text") from None
        elif key in TEXT_ATTRIBUTES:
            raise _damaged(path, f"its attribute {key} is not text")
        elif key in INTEGER_ATTRIBUTES:
            number = np.asarray(value)
            if number.size != 1 or number.dtype.kind not in "iu":
                raise _damaged(path, f"its attribute {key} is not one integer")
            value = int(number.ravel()[0])
        out[key] = value
    return out


def _check_campaign(path, f):
    """The shapes the readers rely on: /replicas columns 1-D of one length R, /timeseries
    [R, S], n_samples of done replicas in [0, S]; returns R."""
    version = f.attrs.get("layout_version")
    if version is not None and int(np.asarray(version).ravel()[0]) > NEWEST_LAYOUT:
        raise AnalysisError(f"'{path}' has archive layout {int(np.asarray(version).ravel()[0])}; this package reads "
                            f"layouts up to {NEWEST_LAYOUT} (a newer jamsim wrote it: use its tools)")
    for name in REQUIRED_COLUMNS:
        if name not in f["replicas"]:
            raise _damaged(path, f"/replicas/{name} is missing (every campaign archive has "
                                 f"/replicas/{{{','.join(REQUIRED_COLUMNS)}}})")
    status = f["replicas/status"]
    if status.ndim != 1:
        raise _damaged(path, f"/replicas/status has shape {status.shape}, not one value per replica")
    rows = status.shape[0]
    for name, ds in f["replicas"].items():
        if isinstance(ds, h5py.Dataset) and ds.shape != (rows,):
            raise _damaged(path, f"/replicas/{name} has shape {ds.shape}; /replicas/status has {rows} replicas")
        if name in REQUIRED_COLUMNS and ds.dtype.kind not in "iuf":
            raise _damaged(path, f"/replicas/{name} holds {ds.dtype}, not numbers")
    width = None
    for name, ds in f["timeseries"].items():
        if not isinstance(ds, h5py.Dataset) or ds.ndim != 2 or ds.shape[0] != rows or ds.dtype.kind not in "iuf":
            raise _damaged(path, f"/timeseries/{name} has shape {getattr(ds, 'shape', None)} and type "
                                 f"{getattr(ds, 'dtype', None)}; {rows} rows of numbers (one per replica) expected")
        if width is not None and ds.shape[1] != width:
            raise _damaged(path, f"/timeseries/{name} has {ds.shape[1]} samples per replica, the other columns "
                                 f"{width}")
        width = ds.shape[1]
    if width is None:
        raise _damaged(path, "/timeseries holds no time series")
    if "strain" not in f["timeseries"]:
        raise _damaged(path, "/timeseries/strain is missing (every archive records the strain of each sample)")
    if "model" not in f.attrs:
        raise _damaged(path, "the root attribute model is missing")
    status_values = status[...]
    unknown = sorted(set(int(v) for v in status_values) - set(STATUS_NAMES))
    if unknown:
        raise _damaged(path, f"/replicas/status holds {unknown[0]} ({', '.join(f'{k} {v}' for k, v in STATUS_NAMES.items())})")
    samples = f["replicas/n_samples"][...].astype(float)
    done = status_values == DONE
    n, phi = f["replicas/N"][...].astype(float), f["replicas/phi"][...].astype(float)
    bad = done & ~((n >= 1) & (n == np.floor(n)) & (phi > 0) & (phi < 1))
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        raise _damaged(path, f"replica {r} is done with N = {n[r]:g}, phi = {phi[r]:g} (N a whole number >= 1, "
                             "0 < phi < 1)")
    if ("rate" in f["replicas"] or "sample_interval" in f["replicas"]) and "transient" not in f["replicas"]:
        raise _damaged(path, "/replicas/transient is missing (every model that reads rate or sample_interval "
                             "records its transient, where its averages start)")
    if "rate" in f["replicas"]:
        rate = f["replicas/rate"][...].astype(float)
        bad = done & (rate < 0)
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise _damaged(path, f"replica {r} is done with rate = {rate[r]:g} (rate >= 0)")
    bad = done & ~((samples >= 0) & (samples <= width) & (samples == np.floor(samples)))
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        raise _damaged(path, f"/replicas/n_samples[{r}] = {samples[r]:g} for a done replica; 0 to the "
                             f"{width} samples of /timeseries")
    _check_bookkeeping(path, f)
    return rows


# The bookkeeping a run writes beside the data, as jamsim's own archive check allows it
# (check_bookkeeping in src/archive/archive_file_check.cpp): column, lowest, highest, NaN
# allowed, whole numbers only, what is allowed.
_MOST_RANKS = 2 ** 20
BOOKKEEPING_RANGES = (
    ("rank", -1, _MOST_RANKS - 1, False, True, "the MPI rank that ran it, from 0, or -1 before it runs"),
    ("progress", 0, 1, False, False, "the fraction of its steps done, from 0 to 1"),
    ("force_evaluations", 0, 9e18, False, True, "a whole count from 0"),
    ("threads", 0, _MOST_RANKS, False, False, "its mean threads, from 0 (0: not recorded)"),
    ("wall_seconds", 0, 1e12, True, False, "its wall time in seconds from 0, or nan before it runs"))


def _check_bookkeeping(path, f):
    """Each replica's rank, progress, force evaluations, threads and wall seconds in their
    ranges, and /replicas/status whole numbers: the summary printed a hand-edited progress of 5
    or a rank of -3 as fact, and read a status of 2.7 as done."""
    if f["replicas/status"].dtype.kind not in "iu":
        raise _damaged(path, f"/replicas/status holds {f['replicas/status'].dtype}, not integers (jamsim writes it so)")
    for name, low, high, nan_allowed, whole, allowed in BOOKKEEPING_RANGES:
        if name not in f["replicas"]:
            continue
        values = f[f"replicas/{name}"][...].astype(float)
        good = (values >= low) & (values <= high) & (~whole | (values == np.floor(values)))
        if nan_allowed:
            good |= np.isnan(values)
        if not good.all():
            r = int(np.flatnonzero(~good)[0])
            raise _damaged(path, f"/replicas/{name}[{r}] is {values[r]:g} ({allowed})")


def _check_replica_file(path, f):
    """The shapes the readers rely on: numeric N, phi, seed, a model name, and /timeseries
    columns 1-D of one length with strain among them."""
    for name in REQUIRED_ATTRIBUTES:
        value = f.attrs.get(name)
        if value is None:
            raise _damaged(path, f"the root attribute {name} is missing")
        if name != "model" and np.asarray(value).dtype.kind not in "iuf":
            raise _damaged(path, f"the root attribute {name} = {_text(np.asarray(value).ravel()[0])!r} is not a number")
    if ("rate" in f.attrs or "sample_interval" in f.attrs) and "transient" not in f.attrs:
        raise _damaged(path, "the root attribute transient is missing (every model that reads rate or "
                             "sample_interval records its transient, where its averages start)")
    rate = f.attrs.get("rate")
    if rate is not None and np.asarray(rate).dtype.kind in "iuf" and float(np.asarray(rate).ravel()[0]) < 0:
        raise _damaged(path, f"the root attribute rate = {float(np.asarray(rate).ravel()[0]):g} is below 0 (rate >= 0)")
    identity = f.attrs.get("identity")
    if identity is not None and isinstance(identity, (bytes, str)):
        try:
            int(_text(identity), 16)
        except ValueError:
            raise _damaged(path, f"the root attribute identity = {_text(identity)!r} is not hexadecimal") from None
    lengths = {}
    for name, ds in f["timeseries"].items():
        if not isinstance(ds, h5py.Dataset) or ds.ndim != 1 or ds.dtype.kind not in "iuf":
            raise _damaged(path, f"/timeseries/{name} has shape {getattr(ds, 'shape', None)}; a 1-D column of numbers "
                                 "expected")
        lengths[name] = ds.shape[0]
    if "strain" not in lengths:
        raise _damaged(path, "/timeseries/strain is missing")
    if len(set(lengths.values())) > 1:
        raise _damaged(path, "the /timeseries columns differ in length (" +
                       ", ".join(f"{k} {v}" for k, v in sorted(lengths.items())) + ")")
