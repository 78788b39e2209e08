#!/usr/bin/env bash
# usage: data_initial_seeds.sh JAMSIM (in a scratch folder)
# A LAMMPS data file as [run] initial starts every replica from its one state: seeds of a
# model that draws no random numbers would be the same bits (false seeds, false error bars),
# and initial_match = "id" picks nothing. Both are refused before any work, nothing written;
# one seed runs, and so do seeds of a thermal model (its seed draws the noise).
set -euo pipefail
jamsim=$1
rm -rf seeds_work && mkdir seeds_work && cd seeds_work
campaign() {  # NAME MODEL SEEDS [EXTRA [run] LINE]
  printf '[campaign]\nname = "%s"\noutput = "%s.h5"\n[model]\nname = "%s"\n[run]\nstrain = 0.05\nsample_interval = 0.01\n%s\n[sweep]\nN = [16]\nphi = [0.84]\nrate = [1e-2]\nseeds = %s\n' \
    "$1" "$1" "$2" "${4:-}" "$3" > "$1.toml"
}
campaign base RD0 1
"$jamsim" run base.toml > /dev/null 2>&1
"$jamsim" export base.h5 -r 0 -o init.data > /dev/null
refused() {  # NAME REGEX
  rc=0
  "$jamsim" run "$1.toml" > "$1.txt" 2>&1 || rc=$?
  cat "$1.txt"
  [[ $rc -eq 2 ]] || { echo "FAIL ($1): exit $rc, not 2"; exit 1; }
  grep -Eq -- "$2" "$1.txt" || { echo "FAIL ($1): no /$2/"; exit 1; }
  [[ ! -e "$1.h5" ]] || { echo "FAIL ($1): $1.h5 written"; exit 1; }
}
campaign seeds RD0 3 'initial = "init.data"'
refused seeds '\[sweep\] seeds: replicas 0 and 1 \(seed 1 and 2\) are not allowed with \[run\] initial = "init.data": .*RD0 draws no random numbers, so they would be the same bits'
campaign by_id RD0 1 'initial = "init.data"
initial_match = "id"'
refused by_id '\[run\] initial_match = "id" is not allowed with \[run\] initial = "init.data": a LAMMPS data file holds one state'
campaign one RD0 1 'initial = "init.data"'
"$jamsim" run one.toml > /dev/null 2>&1
printf '[campaign]\nname = "hot"\noutput = "hot.h5"\n[model]\nname = "RD0T"\ntemperature = 1e-4\n[run]\ntime = 1\nsample_interval = 0.2\ninitial = "init.data"\n[sweep]\nN = [16]\nphi = [0.84]\nrate = [0]\nseeds = 2\n' > hot.toml
"$jamsim" run hot.toml > /dev/null 2>&1
/usr/bin/python3 -c "import h5py, numpy, sys; p = h5py.File('hot.h5')['timeseries/pressure'][:]; sys.exit(numpy.array_equal(p[0], p[1]))" \
  || { echo "FAIL: RD0T seeds from one data file gave the same bits"; exit 1; }
echo "ok: seeds without effect and initial_match = id refused; one seed, and a thermal model's seeds, run"
