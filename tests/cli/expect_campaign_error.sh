#!/usr/bin/env bash
# usage: expect_campaign_error.sh REGEX JAMSIM SPEC [PROTECTED_ARCHIVE]
# Runs `jamsim run SPEC` in the current directory. Passes when it exits non-zero with a
# message matching REGEX that names the spec file, writes no bad-out.h5 (nor its checkpoint
# folder), and leaves PROTECTED_ARCHIVE (if given) byte-for-byte unchanged.
# Optional environment: EXPECT_STATUS, the exact exit status required (2: refused).
regex=$1 jamsim=$2 spec=$3 protected=${4:-}
rm -rf bad-out.h5 bad-out.h5.checkpoints
before=""
[[ -n $protected ]] && before=$(sha256sum "$protected")
msg=$("$jamsim" run "$spec" 2>&1)
rc=$?
echo "$msg"
fail() { echo "FAIL: $*"; exit 1; }
[[ $rc -ne 0 ]] || fail "exit code 0, expected non-zero"
[[ -z $EXPECT_STATUS || $rc -eq $EXPECT_STATUS ]] || fail "exit code $rc, expected $EXPECT_STATUS"
grep -Eq -- "$regex" <<<"$msg" || fail "message does not match /$regex/"
grep -qF -- "$(basename "$spec")" <<<"$msg" || fail "message does not name the file"
! grep -Eq -- "MPI_ABORT|HDF5-DIAG|terminate called|Segmentation" <<<"$msg" || fail "an abort banner or crash in the output"
[[ ! -e bad-out.h5 && ! -e bad-out.h5.checkpoints ]] || fail "an archive was written"
if [[ -n $protected ]]; then
  [[ "$(sha256sum "$protected")" == "$before" ]] || fail "$protected was modified"
fi
echo "ok: exit $rc"
