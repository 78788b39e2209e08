#!/usr/bin/env bash
# usage: make_bad_archives.sh JAMSIM CAMPAIGN.toml
# In the current directory: good.h5 (a finished archive of CAMPAIGN) and one file of each
# kind that is not a usable archive, for the tests of `status`, `run` and `merge` on them:
# empty.h5, text.h5 (not HDF5), truncated.h5, plain.h5 (HDF5, not jamsim), replica.h5 (a
# single-replica file), layout.h5 (another archive layout), version.h5 (another campaign
# fingerprint version), a_directory/; missing.h5 is removed. Damaged copies of good.h5 (its
# datasets edited as by hand): status_rows.h5 (/replicas/status of 2 entries, n_replicas 1),
# status_value.h5 (a status of 9), series_cut.h5 (/timeseries/pressure cut to 2 samples),
# final_cut.h5 (/final/x cut to 3 disks), no_series.h5 (no /timeseries); and two whose layout
# is whole but whose final state jamsim cannot have written: final_nan.h5 (x = nan at disk 3),
# box_negative.h5 (/final/box_side = -1), box_strain_far.h5 (/final/box_strain = 7); ranks_text.h5 (the n_ranks attribute as text);
# n_nan.h5, n_zero.h5, n_huge.h5 (/replicas/N = nan, 0, 1e12), offset_far.h5
# (particle_offset = 1e12), samples_many.h5 (n_samples = 1e9), rows_many.h5 (rows_written 1e9);
# spec_text_bad.h5 (its stored campaign no TOML), spec_text_other.h5 (another campaign's),
# model_edited.h5, phi_edited.h5, no_seed.h5, box_side_text.h5 (against its stored campaign);
# progress_high.h5, rank_negative.h5, evaluations_negative.h5, ranks_negative.h5,
# created_text.h5, status_float.h5 (bookkeeping out of its range or of another class);
# no_cost.h5 (no /replicas/estimated_cost);
# heap_zeroed.h5 and heap_last.h5 (the objects of its first or last global heap zeroed, as a
# crash can leave them: HDF5 1.10 loops for ever reading its attributes; the first holds the
# root's text, the last the datasets' descriptions, which no command reads: the check reads
# them all under the read deadline, as a later reader, h5py's included, would loop on them).
set -euo pipefail
jamsim=$1 spec=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf good.h5 good.h5.checkpoints empty.h5 text.h5 truncated.h5 plain.h5 replica.h5 \
  layout.h5 version.h5 missing.h5 a_directory status_rows.h5 status_value.h5 series_cut.h5 final_cut.h5 \
  no_series.h5 final_nan.h5 box_negative.h5 ranks_text.h5 heap_zeroed.h5 heap_last.h5 n_nan.h5 n_zero.h5 \
  n_huge.h5 offset_far.h5 samples_many.h5 rows_many.h5 spec_text_bad.h5 spec_text_other.h5 model_edited.h5 \
  phi_edited.h5 no_seed.h5 box_side_text.h5 progress_high.h5 rank_negative.h5 evaluations_negative.h5 \
  ranks_negative.h5 created_text.h5 status_float.h5 box_strain_far.h5 no_cost.h5
"$jamsim" run "$spec" -o good.h5 >/dev/null 2>&1
: > empty.h5
echo "not an archive" > text.h5
head -c $(( $(stat -c %s good.h5) / 2 )) good.h5 > truncated.h5
"$jamsim" replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 -o replica.h5 >/dev/null 2>&1
cp good.h5 layout.h5
cp good.h5 version.h5
mkdir a_directory
/usr/bin/python3 - <<'PY'
import h5py
with h5py.File("plain.h5", "w") as f:
    f["x"] = [1.0, 2.0]
with h5py.File("layout.h5", "r+") as f:
    f.attrs["layout_version"] = 2
import shutil
def damaged(name, edit):
    shutil.copy("good.h5", name)
    with h5py.File(name, "r+") as f:
        edit(f)
def replace(f, path, data):
    del f[path]
    f[path] = data
damaged("status_rows.h5", lambda f: replace(f, "replicas/status", [2, 2]))
damaged("status_value.h5", lambda f: f["replicas/status"].__setitem__(0, 9))
damaged("series_cut.h5", lambda f: replace(f, "timeseries/pressure", f["timeseries/pressure"][:, :2]))
damaged("final_cut.h5", lambda f: replace(f, "final/x", f["final/x"][:3]))
damaged("no_series.h5", lambda f: f.__delitem__("timeseries"))
damaged("final_nan.h5", lambda f: f["final/x"].__setitem__(3, float("nan")))
damaged("box_negative.h5", lambda f: f["final/box_side"].__setitem__(0, -1.0))
damaged("no_cost.h5", lambda f: f.__delitem__("replicas/estimated_cost"))
damaged("box_strain_far.h5", lambda f: f["final/box_strain"].__setitem__(0, 7.0))
damaged("ranks_text.h5", lambda f: f.attrs.__setitem__("n_ranks", "two"))
damaged("n_nan.h5", lambda f: f["replicas/N"].__setitem__(0, float("nan")))
damaged("n_zero.h5", lambda f: f["replicas/N"].__setitem__(0, 0.0))
damaged("n_huge.h5", lambda f: f["replicas/N"].__setitem__(0, 1e12))
damaged("offset_far.h5", lambda f: f["replicas/particle_offset"].__setitem__(0, 10**12))
damaged("samples_many.h5", lambda f: f["replicas/n_samples"].__setitem__(0, 1e9))
damaged("rows_many.h5", lambda f: f["replicas/rows_written"].__setitem__(0, 10**9))
damaged("spec_text_bad.h5", lambda f: f.attrs.__setitem__("spec_text", "[campaign]\nname = \"other\"\nthis is not toml"))
damaged("spec_text_other.h5", lambda f: f.attrs.__setitem__("spec_text", f.attrs["spec_text"].replace("0.8", "0.81")))
damaged("model_edited.h5", lambda f: f.attrs.__setitem__("model", "XYZ"))
damaged("phi_edited.h5", lambda f: f["replicas/phi"].__setitem__(0, 0.5))
damaged("no_seed.h5", lambda f: f.__delitem__("replicas/seed"))
damaged("box_side_text.h5", lambda f: replace(f, "final/box_side", [b"x"]))
damaged("progress_high.h5", lambda f: f["replicas/progress"].__setitem__(0, 5.0))
damaged("rank_negative.h5", lambda f: f["replicas/rank"].__setitem__(0, -3))
damaged("evaluations_negative.h5", lambda f: f["replicas/force_evaluations"].__setitem__(0, -1))
damaged("ranks_negative.h5", lambda f: f.attrs.__setitem__("n_ranks", -3))
damaged("created_text.h5", lambda f: f.attrs.__setitem__("created", "not a date"))
damaged("status_float.h5", lambda f: replace(f, "replicas/status", f["replicas/status"][:].astype("f8")))
for name, last in (("heap_zeroed.h5", False), ("heap_last.h5", True)):
    shutil.copy("good.h5", name)
    with open(name, "r+b") as f:  # "GCOL", version, reserved, the collection's size, objects
        data = f.read()
        at = data.rindex(b"GCOL") if last else data.index(b"GCOL")
        size = int.from_bytes(data[at + 8:at + 16], "little")
        f.seek(at + 16)
        f.write(bytes(size - 16))
PY
/usr/bin/python3 "$here/../mpi/other_version.py" version.h5
