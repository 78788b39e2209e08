"""Reading jamsim output: campaign archives (also shards and merged archives) and
single-replica files. This is the only module that touches HDF5; every layout detail (the
layout_version of /final, how /timeseries and /correlation are stored) lives here.

Layouts (campaigns/README.md, "Campaign archive" and "Single-replica file"):
  campaign: /replicas/<column> [R]; /timeseries/<observable> [R, S] (valid up to n_samples
            for done replicas, rows_written otherwise); /correlation/{x,g_y} [R, B] (NaN past a
            replica's bins); /final/box_side, box_strain [R]; /final/{x,y,diameter}:
            layout 3: [R, N_max] (NaN past N); layout 4: 1-D concatenation over replicas with
            /replicas/particle_offset [R] (start of replica r) and the count from /replicas/N.
  replica:  parameters as root attributes; /timeseries/<observable> [S]; /final/{x,y,diameter}
            [N] with attributes box_side and box_strain; /correlation/{x,g_y} [B].
"""
import dataclasses
import math
import os
import signal
import time

import h5py
import numpy as np
import pandas as pd

from .archive_checks import DONE, STATUS_NAMES, _check_campaign, _check_replica_file, _damaged, _root_attributes, _text
from .errors import AnalysisError

# Which row wins when shards of one campaign hold the same replica: done, then failed,
# running, pending.
STATUS_PRIORITY = {2: 3, 3: 2, 1: 1, 0: 0}
# /replicas columns that describe the run, not the physics.
BOOKKEEPING = {"identity", "status", "failure_reason", "rank", "threads", "wall_seconds", "force_evaluations",
               "rows_written", "progress", "n_samples", "estimated_cost", "predecessor",
               "particle_offset"}
# Numeric root attributes of a replica file that are results, not parameters.
REPLICA_FILE_RESULTS = {"mean_pressure", "mean_shear_stress", "force_evaluations",
                        "neighbor_list_builds", "wall_seconds", "layout_version"}
# Models sheared quasistatically (rate 0 in the table, `strain` their total strain).
QUASISTATIC = ("QS", "SHEARED")
# Models whose states are never sheared (no accumulated strain).
UNSHEARED = ("RAND", "COOL", "COMPRESS", "COOL_COMPRESS")
# Largest dataset read whole and kept in memory (elements); larger ones are read by rows.
WHOLE_READ_LIMIT = 20_000_000


@dataclasses.dataclass
class FinalConfiguration:
    """A final configuration. x, y: sheared coordinates in [0, L) [N] (d_s); diameter [N]
    (d_s); box_side L (d_s); box_strain: the Lees-Edwards strain gamma (lab x = x + gamma y)."""
    x: np.ndarray
    y: np.ndarray
    diameter: np.ndarray
    box_side: float
    box_strain: float

    def lab_x(self):
        """Lab-frame x [N] (d_s): x + gamma y, inside the sheared cell's parallelogram."""
        return self.x + self.box_strain * self.y


# Seconds the first look into a file may take (JAMSIM_READ_DEADLINE_SECONDS, as for jamsim):
# HDF5 1.10 loops for ever on some damaged files (a global heap whose objects a crash zeroed).
DEFAULT_READ_DEADLINE = 60.0
_probed = set()  # (path, size, mtime) of files whose first look finished


def _read_deadline():
    """JAMSIM_READ_DEADLINE_SECONDS (unset or empty: 60); refused in words as jamsim refuses it."""
    text = os.environ.get("JAMSIM_READ_DEADLINE_SECONDS", "")
    if not text:
        return DEFAULT_READ_DEADLINE
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not 1 <= seconds < 1e9 or text != text.strip():
        raise AnalysisError(f'JAMSIM_READ_DEADLINE_SECONDS = "{text}" is not allowed: a number of seconds, at least 1 '
                            f"and below 1e9 (unset: {DEFAULT_READ_DEADLINE:g})")
    return seconds


def _probe(path):
    """Read every attribute of `path` once in a child process, within the read deadline: a
    file on which HDF5 loops, or crashes, is refused in words instead of hanging the tool. The
    child's own errors are left to the real open, which says them."""
    try:
        st = os.stat(path)
    except OSError:
        return  # the open says why
    key = (os.path.realpath(path), st.st_size, st.st_mtime_ns)
    if key in _probed:
        return
    seconds = _read_deadline()
    pid = os.fork()
    if pid == 0:  # the child: no output, no cleanup handlers, only its exit status
        code = 0
        try:
            with h5py.File(path, "r", locking=False) as f:
                list(f.attrs.items())
                f.visititems(lambda name, obj: list(obj.attrs.items()))
        except BaseException:
            code = 3
        os._exit(code)
    deadline = time.monotonic() + seconds
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            raise AnalysisError(f"reading '{path}' did not finish within {seconds:g} s: its HDF5 structure is "
                                "damaged (HDF5 loops on some damaged files, such as blocks zeroed by a crash), or "
                                "its filesystem does not answer")
        time.sleep(0.01)
    if os.WIFSIGNALED(status):
        raise AnalysisError(f"reading '{path}' crashed HDF5 (signal {os.WTERMSIG(status)}): its HDF5 structure is "
                            "damaged")
    if os.WEXITSTATUS(status) == 0:
        _probed.add(key)


def _open(path):
    if not path:
        raise AnalysisError("an empty path is not an archive")
    if os.path.exists(path) and not os.path.isfile(path):
        raise AnalysisError(f"'{path}' is not a regular file (a directory, a pipe or a device), not an archive")
    _probe(path)
    try:
        return h5py.File(path, "r", locking=False)
    except (OSError, TypeError) as e:
        if not os.path.exists(path):
            raise AnalysisError(f"'{path}': no such file") from None
        if not h5py.is_hdf5(path):  # a campaign file given for the archive: h5py said "file signature not found"
            raise AnalysisError(f"'{path}' is not an HDF5 file (no HDF5 signature), so not a jamsim archive") from None
        raise AnalysisError(f"cannot open '{path}' as HDF5: {e}") from None


class _Source:
    """One file: its kind ('campaign' or 'replica'), text attributes and cached datasets."""

    def __init__(self, path):
        self.path = path
        self.cache = {}
        if os.path.isdir(path):
            raise AnalysisError(f"'{path}' is a directory, not a jamsim archive")
        with _open(path) as f:
            self.attrs = _root_attributes(path, f)
            if "replicas" in f and "timeseries" in f:
                self.kind = "campaign"
                self.n_rows = _check_campaign(path, f)
            elif "timeseries" in f and "model" in f.attrs:
                self.kind = "replica"
                self.n_rows = 1
                _check_replica_file(path, f)
            else:
                raise AnalysisError(f"'{path}' is neither a jamsim campaign archive (/replicas, "
                                    "/timeseries) nor a single-replica file")
        self.layout_version = int(self.attrs.get("layout_version", 0))

    def read(self, name, rows=None):
        """Dataset `name`, whole or the given rows (first axis)."""
        with _open(self.path) as f:
            if name not in f:
                return None
            ds = f[name]
            if ds.size <= WHOLE_READ_LIMIT:
                if name not in self.cache:
                    self.cache[name] = ds[...]
                data = self.cache[name]
                return data if rows is None else data[np.asarray(rows, dtype=int)]
            if rows is None:
                return ds[...]
            return np.stack([ds[int(r)] for r in rows])


def _campaign_table(src):
    """One row per replica of a campaign archive (the /replicas columns)."""
    with _open(src.path) as f:
        cols = {}
        for name, ds in f["replicas"].items():
            if ds.ndim != 1:
                continue
            data = ds[...]
            if data.dtype.kind in "SO":
                data = np.array([_text(v).rstrip("\x00") for v in data], dtype=object)
            cols[name] = data
    table = pd.DataFrame(cols)
    table["identity"] = table.get("identity", pd.Series(np.zeros(len(table), np.uint64))).astype(np.uint64)
    done = table["status"].to_numpy() == DONE
    written = table["rows_written"].to_numpy() if "rows_written" in table else np.zeros(len(table))
    samples = np.nan_to_num(table["n_samples"].to_numpy(dtype=float))
    table["valid_rows"] = np.where(done, samples, written).astype(int)
    table["row"] = np.arange(len(table))
    return table


def _replica_file_table(src):
    """The one row of a single-replica file (its root attributes)."""
    row = {}
    for k, v in src.attrs.items():
        if isinstance(v, str):
            continue
        if k in REPLICA_FILE_RESULTS:
            continue
        row[k] = float(np.asarray(v).ravel()[0])
    with _open(src.path) as f:
        n = len(f["timeseries/strain"])  # present and as long as every column (_check_replica_file)
    ident = src.attrs.get("identity", "0")
    row.update(identity=np.uint64(int(ident, 16) if isinstance(ident, str) else int(ident)),
               status=DONE, n_samples=float(n), valid_rows=n, row=0,
               wall_seconds=float(src.attrs.get("wall_seconds", np.nan)),
               force_evaluations=int(src.attrs.get("force_evaluations", -1)), failure_reason="")
    return pd.DataFrame([row])


def _merge_shards(sources, tables):
    """Shards of one campaign: per replica row the best-status shard's row."""
    best = tables[0].copy()
    best["source"] = sources[0]
    for src, t in zip(sources[1:], tables[1:]):
        if len(t) != len(best):
            raise AnalysisError(f"'{src.path}' has {len(t)} replicas, '{sources[0].path}' "
                                f"{len(best)}: not shards of one campaign")
        better = t["status"].map(STATUS_PRIORITY).to_numpy() > best["status"].map(STATUS_PRIORITY).to_numpy()
        t = t.copy()
        t["source"] = src
        best.loc[better] = t.loc[better]
    return best


# Columns that are not settings of the run (compared when two files hold one replica).
NOT_SETTINGS = BOOKKEEPING | {"valid_rows", "row", "source", "campaign", "model", "seed", "failure_reason",
                              "checkpoint_steps"}


def _drop_duplicates(table):
    """One row per replica (identity and seed; rows of identity 0 all kept): the best status,
    the first on a tie. The same replica with other run settings (strain, dt, sampling, ...)
    is refused: its results are not the same."""
    if "seed" not in table:
        return table
    ident = table["identity"].to_numpy(np.uint64)
    seed = table["seed"].to_numpy(float)
    rank = table["status"].map(STATUS_PRIORITY).to_numpy()
    settings = [c for c in table.columns if c not in NOT_SETTINGS and table[c].dtype.kind in "fiub"]
    keep = np.ones(len(table), bool)
    best = {}
    for k in range(len(table)):
        if ident[k] == 0:
            continue
        key = (int(ident[k]), float(seed[k]))
        j = best.get(key)
        if j is None:
            best[key] = k
            continue
        for c in settings:
            a, b = float(table[c].iat[j]), float(table[c].iat[k])
            if np.isfinite(a) and np.isfinite(b) and a != b:
                raise AnalysisError(
                    f"'{table['source'].iat[j].path}' and '{table['source'].iat[k].path}' hold the same replica "
                    f"(N = {table['N'].iat[k]:g}, phi = {table['phi'].iat[k]:g}, seed = {seed[k]:g}) run with "
                    f"other settings ({c} = {a:g} and {b:g}): read one of them")
        if rank[k] > rank[j]:
            keep[j] = False
            best[key] = k
        else:
            keep[k] = False
    return table[keep].reset_index(drop=True)


class Archive:
    """One or more jamsim output files as one table of replicas.

    replicas: DataFrame, one row per replica: `replica` (index used by every method), `file`,
      `campaign`, `model`, every parameter column (N, phi, rate, seed, ...; NaN where the
      model does not read it), `status` (0..3) and `status_name`, `n_samples`,
      `valid_rows` (rows of the time series that may be read), `wall_seconds` (s),
      `force_evaluations`, `failure_reason`, `identity`.
    Shards of one campaign (the same spec_fingerprint and replica count) are merged: each
    replica comes from the shard where it is done. Archives of other campaigns (other
    sweeps, a campaign and its grown or merged version) are put together; a replica that
    several of them hold (the same identity and seed, i.e. the same model, physical
    parameters and seed) is counted once, from the file where its status is best (done,
    failed, running, pending; the first file given on a tie), and refused when its run
    settings (strain, dt, sampling, ...) differ between the files. Replicas of archives made
    before stable identity (identity 0) are never taken for one another."""

    def __init__(self, paths):
        if not paths:
            raise AnalysisError("no archive given")
        sources = [_Source(p) for p in paths]
        groups = {}
        for s in sources:
            key = (s.attrs.get("spec_fingerprint"), s.n_rows) if s.kind == "campaign" else (s.path,)
            groups.setdefault(key, []).append(s)
        parts = []
        for members in groups.values():
            tables = [_campaign_table(s) if s.kind == "campaign" else _replica_file_table(s) for s in members]
            merged = _merge_shards(members, tables)
            first = members[0]
            merged["campaign"] = first.attrs.get("campaign", os.path.basename(first.path))
            merged["model"] = first.attrs.get("model", "")
            parts.append(merged)
        table = _drop_duplicates(pd.concat(parts, ignore_index=True, sort=False))
        table["file"] = [s.path for s in table["source"]]
        table["status_name"] = table["status"].map(STATUS_NAMES)
        table["replica"] = np.arange(len(table))
        self._sources = table.pop("source").to_list()
        self._rows = table["row"].to_numpy()
        self.replicas = table
        self.sources = sources

    # -- metadata -----------------------------------------------------------------------
    @property
    def models(self):
        """Sorted list of the models in these files."""
        return sorted(set(self.replicas["model"]))

    def attributes(self, replica=0):
        """Root attributes (dict) of the file holding `replica`: campaign, model, spec_text,
        code_version, layout_version, ..."""
        return dict(self._sources[replica].attrs)

    def done(self):
        """The replicas table restricted to finished replicas."""
        return self.replicas[self.replicas["status"] == DONE]

    def why_none_done(self):
        """Where the replicas stand when none is done, in words: '3 failed (replica 0: REASON),
        1 pending'."""
        counts = self.replicas["status"].map(STATUS_NAMES).value_counts()
        parts = [f"{counts[name]} {name}" for name in ("failed", "running", "pending") if name in counts]
        failed = self.replicas[self.replicas["status"] == 3]
        if not failed.empty and "failure_reason" in failed:
            first = failed.iloc[0]
            parts[0] += f" (replica {int(first['replica'])}: {_text(first['failure_reason'])})"
        return ", ".join(parts) or "no replicas"

    def observables(self):
        """Names of the time-series columns present in every file."""
        names = None
        for s in self.sources:
            with _open(s.path) as f:
                here = set(f["timeseries"].keys())
            names = here if names is None else names & here
        return sorted(names)

    # -- time series ----------------------------------------------------------------------
    def series(self, replica, column):
        """One replica's time series of `column` [valid_rows] (units of the column)."""
        src, row = self._sources[replica], self._rows[replica]
        n = int(self.replicas["valid_rows"].iat[replica])
        name = f"timeseries/{column}"
        if src.kind == "replica":
            data = src.read(name)
        else:
            data = src.read(name, [row])
            data = None if data is None else data[0]
        if data is None:
            with _open(src.path) as f:
                have = ", ".join(sorted(f["timeseries"].keys()))
            raise AnalysisError(f"'{src.path}' has no time series '{column}' (it has: {have})")
        return np.asarray(data[:n], dtype=float)

    def timeseries(self, columns=None, replicas=None, only_done=True):
        """Time series in long form: one row per (replica, sample) with the columns
        `replica`, `sample` and one per observable (default: every observable)."""
        columns = list(columns) if columns is not None else self.observables()
        table = self.done() if only_done else self.replicas
        chosen = table["replica"].to_list() if replicas is None else list(replicas)
        frames = []
        for r in chosen:
            data = {c: self.series(r, c) for c in columns}
            n = min((len(v) for v in data.values()), default=0)
            frame = pd.DataFrame({c: v[:n] for c, v in data.items()})
            frame.insert(0, "sample", np.arange(n))
            frame.insert(0, "replica", r)
            frames.append(frame)
        if not frames:
            return pd.DataFrame(columns=["replica", "sample"] + columns)
        return pd.concat(frames, ignore_index=True)

    # -- per-replica arrays ---------------------------------------------------------------
    def final(self, replica):
        """The final configuration of `replica` (FinalConfiguration), whatever the layout."""
        src, row = self._sources[replica], self._rows[replica]
        n = int(self.replicas["N"].iat[replica])
        return _read_final(src, row, n)

    def final_strain(self, replica):
        """Accumulated strain of the final configuration of `replica` (not the wrapped
        Lees-Edwards offset box_strain in [-1/2, 1/2)): the run's `strain` parameter for a
        sheared run (rate > 0; QS and SHEARED, whose rate is 0), moved to the whole step the
        run ended on (the value congruent to box_strain modulo 1 within two steps of the
        parameter), else the last `strain` sample when it is finite; 0 for dynamics at rate 0;
        NaN for models that do not shear
        (RAND, COMPRESS, ...)."""
        rep = self.replicas.iloc[replica]
        rate = float(rep["rate"]) if "rate" in rep and pd.notna(rep["rate"]) else np.nan
        total = float(rep["strain"]) if "strain" in rep and pd.notna(rep["strain"]) else np.nan
        if np.isfinite(total) and (rate > 0 or rep["model"] in QUASISTATIC):
            # the run ends on a whole step: the strain congruent to the box offset nearest
            # the parameter, when that is within two steps of it
            step = rate * float(rep["dt"]) if rate > 0 and "dt" in rep and pd.notna(rep["dt"]) else \
                float(rep["strain_step"]) if "strain_step" in rep and pd.notna(rep["strain_step"]) else 0.0
            box = self.final(replica).box_strain
            shift = (box - total + 0.5) % 1.0 - 0.5
            return total + shift if abs(shift) <= 2 * step + 1e-12 else total
        if rep["model"] in UNSHEARED:
            return float("nan")
        if rate == 0 and rep["model"] not in QUASISTATIC:
            return 0.0
        try:
            samples = self.series(replica, "strain")
        except AnalysisError:
            return float("nan")
        return float(samples[-1]) if len(samples) and np.isfinite(samples[-1]) else float("nan")

    def has_frames(self, replica):
        """Whether the file of `replica` keeps configuration frames ([run] frame_interval)."""
        src = self._sources[replica]
        return src.kind == "campaign" and src.read("frames/strain") is not None

    def frames(self, replica):
        """Configuration frames of `replica`: (strain [F] (time at rate 0), list of F
        FinalConfiguration in tag order, sheared coordinates in [0, L); diameters and L from
        the final configuration). Only the frames written (strain not NaN)."""
        src, row = self._sources[replica], self._rows[replica]
        if not self.has_frames(replica):
            raise AnalysisError(f"'{src.path}' keeps no configuration frames (set [run] frame_interval)")
        final = self.final(replica)
        n = len(final.x)
        strain = np.asarray(src.read("frames/strain", [row])[0], float)
        box = np.asarray(src.read("frames/box_strain", [row])[0], float)
        valid = np.flatnonzero(np.isfinite(strain))
        with _open(src.path) as f:
            start = int(f["replicas/particle_offset"][row])
            cols = slice(start, start + n)
            out = [FinalConfiguration(f["frames/x"][k, cols], f["frames/y"][k, cols], final.diameter,
                                      final.box_side, float(box[k])) for k in valid]
        return strain[valid], out

    def correlation(self, replica):
        """Velocity correlation of `replica`: (x [B] in d_s, g_y [B]); empty arrays if the
        file has none."""
        src, row = self._sources[replica], self._rows[replica]
        x, g = src.read("correlation/x"), src.read("correlation/g_y")
        if x is None or g is None:
            return np.empty(0), np.empty(0)
        if src.kind == "campaign":
            x, g = x[row], g[row]
        keep = np.isfinite(x) & np.isfinite(g)
        return np.asarray(x[keep], float), np.asarray(g[keep], float)


def _read_final(src, row, n):
    """Final configuration of row `row` (N = n) of a source, for every layout; a cell side
    that is not finite and > 0, or a strain that is not finite, is refused."""
    final = _read_final_unchecked(src, row, n)
    if not (np.isfinite(final.box_side) and final.box_side > 0 and np.isfinite(final.box_strain)):
        raise _damaged(src.path, f"the final cell of replica row {row} has side {final.box_side:g} and strain "
                                 f"{final.box_strain:g} (a side > 0 and a finite strain)")
    return final


def _read_final_unchecked(src, row, n):
    if src.kind == "replica":
        with _open(src.path) as f:
            g = f["final"]
            return FinalConfiguration(g["x"][...], g["y"][...], g["diameter"][...],
                                      float(g.attrs["box_side"]), float(g.attrs["box_strain"]))
    with _open(src.path) as f:
        if "final/x" not in f:
            raise AnalysisError(f"'{src.path}' has no /final configurations")
        g = f["final"]
        if g["x"].ndim == 1:  # layout 4: concatenated, offsets per replica
            if "replicas/particle_offset" not in f:
                raise AnalysisError(f"'{src.path}': 1-D /final without /replicas/particle_offset")
            start = int(f["replicas/particle_offset"][row])
            part = slice(start, start + n)
            x, y, d = g["x"][part], g["y"][part], g["diameter"][part]
        else:  # layout 3: [R, N_max], NaN past N
            x, y, d = g["x"][row, :n], g["y"][row, :n], g["diameter"][row, :n]
        return FinalConfiguration(x, y, d, float(g["box_side"][row]), float(g["box_strain"][row]))


def open_archives(*paths):
    """Open one or more campaign archives, shards or single-replica files as an Archive."""
    flat = [p for item in paths for p in ([item] if isinstance(item, str) else item)]
    return Archive(flat)
