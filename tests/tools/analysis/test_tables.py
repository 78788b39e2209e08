"""Data out: the per-replica and per-group tables as xarray Datasets over the sweep's grid,
and the flat CSV of per-replica means (jamsim_analyze.py csv)."""
import csv
import math
import os

import numpy as np
import pandas as pd
import pytest

import jamsim_analysis as ja
from jamsim_analysis import cli

OBS = ["pressure", "shear_stress"]


@pytest.fixture(scope="module")
def flow_table(flow_archive):
    return ja.replica_averages(ja.open_archives(flow_archive), OBS)


def test_replica_dataset_is_the_table_on_the_grid(flow_archive, flow_table):
    ds = ja.replica_dataset(ja.open_archives(flow_archive), OBS)
    # analysis_flow.toml: N = 64, 4 phi x 3 rates x 3 seeds
    assert dict(ds.sizes) == {"N": 1, "phi": 4, "rate": 3, "seed": 3}
    assert list(ds["phi"].values) == [0.80, 0.83, 0.86, 0.89]
    assert list(ds["rate"].values) == [1e-3, 3e-3, 1e-2]
    assert ds["N"].dtype == np.int64 and list(ds["seed"].values) == [1, 2, 3]
    assert ds.attrs["model"] == "RD0"
    # every cell holds its own replica's values, bitwise
    for _, row in flow_table.iterrows():
        cell = ds.sel(N=int(row["N"]), phi=row["phi"], rate=row["rate"], seed=int(row["seed"]))
        assert int(cell["replica"]) == row["replica"]
        assert cell["left_out"].item() == row["left_out"]
        for o in OBS + [f"{o}_error" for o in OBS]:
            a, b = float(cell[o]), row[o]
            assert a == b or (math.isnan(a) and math.isnan(b)), (o, row["replica"])


def test_group_dataset_averages_over_seeds(flow_table):
    groups = ja.group_averages(flow_table, OBS)
    gs = ja.group_dataset(groups, OBS)
    assert dict(gs.sizes) == {"N": 1, "phi": 4, "rate": 3}
    for _, row in groups.iterrows():
        cell = gs.sel(N=int(row["N"]), phi=row["phi"], rate=row["rate"])
        assert float(cell["pressure"]) == row["pressure"]
        assert int(cell["seeds"]) == row["seeds"]
    # the Dataset's mean over seeds of the kept replicas is the group average
    ds = ja.to_dataset(flow_table)
    kept = ds["pressure"].where(ds["left_out"] == "")
    assert np.allclose(kept.mean("seed").values, gs["pressure"].values, rtol=1e-14, equal_nan=True)


def test_minimisation_protocol_has_no_rate_dimension(rand_archive):
    ds = ja.replica_dataset(ja.open_archives(rand_archive), ["pressure"])
    # analysis_rand.toml: N = 16, 32, 64; 7 phi; 8 seeds; RAND reads no rate
    assert dict(ds.sizes) == {"N": 3, "phi": 7, "seed": 8}
    assert "rate" not in ds.coords


def test_a_sweep_off_the_grid_is_refused(small_archive):
    # small.toml: 2 N x 2 phi x 2 rates x 2 seeds plus points = [{N = 64, phi = 0.9, rate = 1e-2}]
    run = ja.open_archives(small_archive)
    with pytest.raises(ja.AnalysisError, match=r"the sweep is not a grid: 18 replicas over 2 N x 3 phi x 3 rate "
                                               r"x 2 seed = 36 cells"):
        ja.to_dataset(run.replicas)


def test_two_models_or_duplicate_cells_are_refused(flow_table):
    twice = pd.concat([flow_table, flow_table], ignore_index=True)
    with pytest.raises(ja.AnalysisError, match=r"two replicas share N = 64, phi = 0.8, rate = 0.01, seed = 1 \(rows 0, 36\)"):
        ja.to_dataset(twice)
    other = flow_table.copy()
    other.loc[0, "model"] = "CD0"
    with pytest.raises(ja.AnalysisError, match="replicas of models CD0, RD0: a Dataset holds one model"):
        ja.to_dataset(other)
    assert dict(ja.to_dataset(other, model="CD0").sizes) == {"N": 1, "phi": 1, "rate": 1, "seed": 1}


def test_csv_of_replica_means(flow_archive, flow_table, tmp_path):
    out = str(tmp_path / "means.csv")
    assert cli.analyze_main(["csv", flow_archive, "-o", out, "--observable"] + OBS) == 0
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(flow_table) == 36
    assert list(rows[0])[:7] == ["replica", "campaign", "model", "N", "phi", "rate", "seed"]
    assert "pressure_error" in rows[0] and "shear_stress_tau" in rows[0]
    for row, (_, ref) in zip(rows, flow_table.iterrows()):
        assert int(row["replica"]) == ref["replica"] and int(row["N"]) == 64 and int(row["seed"]) == ref["seed"]
        for o in OBS + ["pressure_error"]:
            # the text reads back as the same double (empty for NaN)
            assert (row[o] == "" and math.isnan(ref[o])) or float(row[o]) == ref[o]
    back = pd.read_csv(out, float_precision="round_trip")
    assert np.array_equal(back["pressure"].to_numpy(), flow_table["pressure"].to_numpy(), equal_nan=True)


def test_csv_refusals_write_nothing(flow_archive, tmp_path, capsys):
    out = tmp_path / "means.csv"
    out.write_text("keep me\n")
    assert cli.analyze_main(["csv", flow_archive, "-o", str(out)]) == 2
    assert "exists: choose another output" in capsys.readouterr().err
    assert out.read_text() == "keep me\n"
    missing = tmp_path / "none.csv"
    assert cli.analyze_main(["csv", str(tmp_path / "nothing.h5"), "-o", str(missing)]) == 2
    assert "no such file" in capsys.readouterr().err
    assert cli.analyze_main(["csv", flow_archive, "-o", str(missing), "--observable", "presure"]) == 2
    assert "--observable presure is not allowed" in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path)) == ["means.csv"]
