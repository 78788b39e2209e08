#!/usr/bin/env bash
# usage: lammps_out_of_reach.sh JAMSIM (in the folder of good.h5, make_bad_archives.sh)
# LAMMPS data files whose tilt or atoms cannot be folded into the cell are refused as
# --initial, naming the line or atom: a tilt of nan (it was read as a section name and the
# tilt as 0), a tilt of 1e308 (folded to 0), an atom at x = 1e308. The file they are made
# from starts a replica.
set -euo pipefail
jamsim=$1
rm -f g.data lq.h5
"$jamsim" export good.h5 -r 0 -o g.data > /dev/null
sed 's/^[0-9.e+-]* 0 0 xy xz yz/nan 0 0 xy xz yz/' g.data > tilt_nan.data
sed 's/^[0-9.e+-]* 0 0 xy xz yz/1e308 0 0 xy xz yz/' g.data > tilt_big.data
sed '0,/^1 1 1 1 [0-9.e+-]*/s//1 1 1 1 1e308/' g.data > atom_far.data
declare -A want=(
  [tilt_nan]="line [0-9]+: 'nan 0 0 xy xz yz': finite numbers before 'xy xz yz'"
  [tilt_big]="tilt xy = 1e\+308 is not allowed: \|xy\| <= 2\^20"
  [atom_far]="atom 1 at \(1e\+308, [0-9.e+-]+\) is not allowed: within 2\^20 cell sides of the cell")
for f in tilt_nan tilt_big atom_far; do
  rc=0
  "$jamsim" replica --N 64 --phi 0.8 --rate 1e-2 --strain 0.01 --initial "$f.data" -o lq.h5 > lq.txt 2>&1 || rc=$?
  cat lq.txt
  [[ $rc -eq 2 ]] || { echo "FAIL ($f): exit $rc, not 2"; exit 1; }
  grep -Eq -- "${want[$f]}" lq.txt || { echo "FAIL ($f): no /${want[$f]}/"; exit 1; }
  [[ ! -e lq.h5 ]] || { echo "FAIL ($f): lq.h5 written"; exit 1; }
done
"$jamsim" replica --N 64 --phi 0.8 --rate 1e-2 --strain 0.01 --initial g.data -o lq.h5 > /dev/null 2>&1
rm lq.h5
echo "ok: three files out of reach refused, the exported one starts a replica"
