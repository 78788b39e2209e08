#!/usr/bin/env bash
# usage: output_line_break.sh JAMSIM CAMPAIGN.toml WORKDIR
# An output path with a line break is refused by run, replica and export (exit 2, one message,
# nothing made): the command line took it where a campaign file's output refused it.
set -euo pipefail
jamsim=$1 campaign=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$jamsim" run "$campaign" -o ok.h5 > /dev/null
before=$(ls -A)
check() {
  local rc=0
  "$@" > out.txt 2>&1 || rc=$?
  [[ $rc -eq 2 ]] || { cat out.txt; echo "FAIL: exit $rc, expected 2: $*"; exit 1; }
  grep -q "is not allowed: a path without line breaks or control characters" out.txt || { cat out.txt; exit 1; }
  rm out.txt
  [[ "$(ls -A)" == "$before" ]] || { echo "FAIL: files made: $(ls -A)"; exit 1; }
}
check "$jamsim" run "$campaign" -o $'a\nb.h5'
check "$jamsim" replica --N 16 -o $'a\nb.h5'
check "$jamsim" export ok.h5 -r 0 -o $'e\nx.data'
check "$jamsim" minimize --N 16 --lammps-data $'m\nx.data'
echo "ok: a line break in an output path refused by run, replica, export and minimize"
