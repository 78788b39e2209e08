#!/usr/bin/env bash
# Checks that every C++ source under ROOT's src, include and tests (or the files given after
# ROOT) is formatted as ROOT/.clang-format says; names each file that is not, and exits 1.
# Usage: clang_format.sh ROOT [FILE...]
set -euo pipefail
root=$1
shift
cd "$root"
if (($# == 0)); then
  mapfile -t files < <(find src include tests -name '*.cpp' -o -name '*.hpp' | sort)
else
  files=("$@")
fi
bad=0
for f in "${files[@]}"; do
  if ! clang-format --style=file --dry-run -Werror "$f" >/dev/null 2>&1; then
    echo "not formatted: $f (run: clang-format -i $f)"
    bad=$((bad + 1))
  fi
done
if ((bad > 0)); then
  echo "FAIL: $bad of ${#files[@]} files differ from .clang-format"
  exit 1
fi
echo "all ${#files[@]} files formatted as .clang-format says"
