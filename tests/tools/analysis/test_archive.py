"""The loader on real archives made by jamsim from tests/data/campaigns: the replica table
against the campaign file, time series, final configurations in layouts 3 and 4, shards,
replicas not done, single-replica files and bad input."""
import os
import shutil
import subprocess
import tomllib

import h5py
import numpy as np
import pytest

import jamsim_analysis as ja
from conftest import CAMPAIGNS


def campaign(name):
    with open(os.path.join(CAMPAIGNS, f"{name}.toml"), "rb") as f:
        return tomllib.load(f)


def test_replica_table_matches_the_campaign(flow_archive):
    spec = campaign("analysis_flow")
    run = ja.open_archives(flow_archive)
    t = run.replicas
    sweep = spec["sweep"]
    expected = {(n, phi, rate, seed) for n in sweep["N"] for phi in sweep["phi"] for rate in sweep["rate"]
                for seed in range(sweep["seeds"])}
    seeds = sorted(t["seed"].unique())
    assert len(seeds) == sweep["seeds"]
    got = {(int(r.N), r.phi, r.rate, seeds.index(r.seed)) for r in t.itertuples()}
    assert got == expected and len(t) == len(expected)
    assert (t["status_name"] == "done").all() and (t["model"] == "RD0").all()
    assert (t["force_evaluations"] > 0).all() and (t["wall_seconds"] > 0).all()
    assert (t["transient"] == spec["run"]["transient"]).all()
    assert run.attributes()["layout_version"] == 4


def test_time_series_long_form(flow_archive):
    run = ja.open_archives(flow_archive)
    step = campaign("analysis_flow")["run"]["sample_interval"]
    long = run.timeseries(["strain", "pressure"])
    assert len(long) == run.replicas["n_samples"].sum()
    for r, part in long.groupby("replica"):
        # samples every sample_interval of strain, rounded to whole steps of rate * dt
        rep = run.replicas.iloc[r]
        gaps = np.diff(part["strain"])
        assert np.allclose(gaps, gaps[0]) and abs(gaps[0] - step) <= rep["rate"] * rep["dt"] / 2 + 1e-12
        assert np.array_equal(part["pressure"].to_numpy(), run.series(r, "pressure"))
        assert np.all(np.isfinite(part["pressure"]))


def test_final_configuration_layout_3_and_4(flow_archive, copy_of):
    run = ja.open_archives(flow_archive)
    for r in run.replicas["replica"]:
        f, rep = run.final(r), run.replicas.iloc[r]
        assert len(f.x) == rep["N"] and np.all(np.isfinite(f.x))
        assert sorted(np.unique(f.diameter)) == [1.0, 1.4] and np.sum(f.diameter == 1.0) == rep["N"] / 2
        assert np.isclose(np.sum(np.pi * f.diameter ** 2 / 4) / f.box_side ** 2, rep["phi"])
        assert np.all((f.x >= 0) & (f.x < f.box_side) & (f.y >= 0) & (f.y < f.box_side))
    # the same archive rewritten in layout 3 (one NaN-padded row per replica in /final)
    path = copy_of(flow_archive, "layout3.h5")
    with h5py.File(path, "r+") as h:
        n = h["replicas/N"][...].astype(int)
        offsets = h["replicas/particle_offset"][...]
        for name in ("x", "y", "diameter"):
            rows = np.full((len(n), n.max()), np.nan)
            flat = h[f"final/{name}"][...]
            for k in range(len(n)):
                rows[k, : n[k]] = flat[offsets[k]: offsets[k] + n[k]]
            del h[f"final/{name}"]
            h[f"final/{name}"] = rows
        del h["replicas/particle_offset"]
        h.attrs["layout_version"] = np.int64(3)
    v4 = ja.open_archives(path)
    for r in run.replicas["replica"]:
        a, b = run.final(r), v4.final(r)
        for name in ("x", "y", "diameter", "box_side", "box_strain"):
            assert np.array_equal(getattr(a, name), getattr(b, name))


def test_shards_merge_to_the_whole(flow_archive, copy_of):
    whole = ja.open_archives(flow_archive)
    shards = [copy_of(flow_archive, f"shard_{k}.h5") for k in range(2)]
    for k, path in enumerate(shards):
        with h5py.File(path, "r+") as h:
            status = h["replicas/status"][...]
            status[np.arange(len(status)) % 2 != k] = 0  # the other shard's replicas pending
            h["replicas/status"][...] = status
            ts = h["timeseries/pressure"][...]
            ts[np.arange(len(status)) % 2 != k] = np.nan
            h["timeseries/pressure"][...] = ts
    merged = ja.open_archives(*shards)
    assert len(merged.replicas) == len(whole.replicas) and (merged.replicas["status"] == 2).all()
    for r in whole.replicas["replica"]:
        assert np.array_equal(merged.series(r, "pressure"), whole.series(r, "pressure"))
    assert [os.path.basename(p) for p in merged.replicas["file"][:2]] == ["shard_0.h5", "shard_1.h5"]


def test_replica_not_done_reads_rows_written_and_is_left_out(flow_archive, copy_of):
    path = copy_of(flow_archive, "running.h5")
    with h5py.File(path, "r+") as h:
        h["replicas/status"][0] = 1
        h["replicas/rows_written"][0] = 5
    run = ja.open_archives(path)
    assert run.replicas["valid_rows"].iloc[0] == 5 and len(run.series(0, "pressure")) == 5
    table = ja.replica_averages(run, ["pressure"])
    assert table["left_out"].iloc[0] == "status running"
    assert not table["left_out"].iloc[1:].str.startswith("status").any()


def test_single_replica_file(jamsim, tmp_path):
    out = tmp_path / "one.h5"
    subprocess.run([jamsim, "replica", "--model", "RD0", "--N", "64", "--phi", "0.84", "--rate", "1e-2",
                    "--strain", "0.3", "--transient", "0.1", "--seed", "3", "-o", str(out)],
                   check=True, capture_output=True)
    run = ja.open_archives(str(out))
    rep = run.replicas.iloc[0]
    assert len(run.replicas) == 1 and rep["N"] == 64 and rep["phi"] == 0.84 and rep["seed"] == 3
    assert rep["status_name"] == "done" and rep["force_evaluations"] > 0
    strain = run.series(0, "strain")
    assert len(strain) == rep["n_samples"] and np.isclose(strain[-1], 0.3, atol=0.02)
    f = run.final(0)
    assert len(f.x) == 64 and np.isclose(np.sum(np.pi * f.diameter ** 2 / 4) / f.box_side ** 2, 0.84)
    x, g = run.correlation(0)
    assert len(x) > 3 and np.all(np.isfinite(g))
    with h5py.File(out, "r") as h:  # the recorded steady mean is the mean over strain >= transient
        recorded = h.attrs["mean_pressure"]
    p = run.series(0, "pressure")
    assert np.isclose(p[strain >= 0.1 - 1e-9].mean(), recorded, rtol=1e-9)


def test_bad_input_is_refused(tmp_path):
    with pytest.raises(ja.AnalysisError, match="missing.h5"):
        ja.open_archives(str(tmp_path / "missing.h5"))
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as h:
        h["data"] = np.zeros(3)
    with pytest.raises(ja.AnalysisError, match="neither a jamsim campaign archive"):
        ja.open_archives(str(other))
    text = tmp_path / "text.h5"
    text.write_text("not hdf5")
    with pytest.raises(ja.AnalysisError, match="is not an HDF5 file"):
        ja.open_archives(str(text))
