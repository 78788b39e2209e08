#!/usr/bin/env bash
# usage: replica_file_check.sh JAMSIM CHECKER.py OUT.h5
set -euo pipefail
jamsim=$1 checker=$2 out=$3
rm -f "$out"
"$jamsim" replica --model RD0 --N 64 --phi 0.8 --rate 1e-3 --strain 0.3 --transient 0.1 \
    --sample-interval 0.01 --seed 5 -o "$out" | tee "$out.log"
/usr/bin/python3 "$checker" "$out" "$out.log"
