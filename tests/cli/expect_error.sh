#!/usr/bin/env bash
# usage: expect_error.sh REGEX OUTPUT_FILE COMMAND...
# Passes when COMMAND exits non-zero, its stderr+stdout matches REGEX, and OUTPUT_FILE
# (and OUTPUT_FILE.tmp) do not exist afterwards.
regex=$1 out=$2
shift 2
rm -f "$out" "$out.tmp"
msg=$("$@" 2>&1)
rc=$?
echo "$msg"
if [[ $rc -eq 0 ]]; then echo "FAIL: exit code 0, expected non-zero"; exit 1; fi
if ! grep -Eq -- "$regex" <<<"$msg"; then echo "FAIL: message does not match /$regex/"; exit 1; fi
if [[ -e "$out" || -e "$out.tmp" ]]; then echo "FAIL: $out was written"; exit 1; fi
echo "ok: exit $rc"
