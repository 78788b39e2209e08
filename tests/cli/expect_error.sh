#!/usr/bin/env bash
# usage: expect_error.sh REGEX OUTPUT_FILE COMMAND...
# Passes when COMMAND exits non-zero, its stderr+stdout matches REGEX, and OUTPUT_FILE
# (and OUTPUT_FILE.tmp, OUTPUT_FILE.XXXXXX.tmp) do not exist afterwards.
# Optional environment: EXPECT_STATUS, the exact exit status required (2 for usage errors);
# PROTECT, files (separated by spaces) that must be byte-for-byte unchanged (sha256).
# Never passes with an MPI abort banner, an HDF5 error stack or a crash in the output.
regex=$1 out=$2
shift 2
rm -f "$out" "$out.tmp" "$out".??????.tmp
declare -A before
for f in $PROTECT; do before[$f]=$(sha256sum "$f" 2>/dev/null || echo absent); done
msg=$("$@" 2>&1)
rc=$?
echo "$msg"
if [[ $rc -eq 0 ]]; then echo "FAIL: exit code 0, expected non-zero"; exit 1; fi
if [[ -n $EXPECT_STATUS && $rc -ne $EXPECT_STATUS ]]; then echo "FAIL: exit code $rc, expected $EXPECT_STATUS"; exit 1; fi
if ! grep -Eq -- "$regex" <<<"$msg"; then echo "FAIL: message does not match /$regex/"; exit 1; fi
if grep -Eq -- "MPI_ABORT|HDF5-DIAG|terminate called|Segmentation|Traceback" <<<"$msg"; then
  echo "FAIL: an abort banner, error stack or crash in the output"; exit 1
fi
if [[ -e "$out" || -e "$out.tmp" ]] || compgen -G "$out.??????.tmp" > /dev/null; then echo "FAIL: $out was written"; exit 1; fi
for f in $PROTECT; do
  now=$(sha256sum "$f" 2>/dev/null || echo absent)
  if [[ "$now" != "${before[$f]}" ]]; then echo "FAIL: $f was created or changed"; exit 1; fi
done
echo "ok: exit $rc"
