#!/usr/bin/env bash
# usage: expect_campaign_error.sh REGEX JAMSIM SPEC [PROTECTED_ARCHIVE]
# Runs `jamsim run SPEC` in the current directory. Passes when it exits non-zero with a
# message matching REGEX that names the spec file, writes no bad-out.h5, and leaves
# PROTECTED_ARCHIVE (if given) byte-for-byte unchanged.
regex=$1 jamsim=$2 spec=$3 protected=${4:-}
rm -f bad-out.h5
before=""
[[ -n $protected ]] && before=$(sha256sum "$protected")
msg=$("$jamsim" run "$spec" 2>&1)
rc=$?
echo "$msg"
fail() { echo "FAIL: $*"; exit 1; }
[[ $rc -ne 0 ]] || fail "exit code 0, expected non-zero"
grep -Eq -- "$regex" <<<"$msg" || fail "message does not match /$regex/"
grep -qF -- "$(basename "$spec")" <<<"$msg" || fail "message does not name the file"
[[ ! -e bad-out.h5 ]] || fail "an archive was written"
if [[ -n $protected ]]; then
  [[ "$(sha256sum "$protected")" == "$before" ]] || fail "$protected was modified"
fi
echo "ok: exit $rc"
