#!/usr/bin/env bash
# usage: deadline_variables.sh JAMSIM
# JAMSIM_READ_DEADLINE_SECONDS and JAMSIM_WRITE_DEADLINE_SECONDS not a number of seconds
# at least 1 and below 1e9: one message naming the variable, its value and what is allowed, exit
# 2, before any command runs (a value such as "abc" or "5s" used to stand silently for the
# default). Valid and empty values are taken.
set -u
jamsim=$1
fail() { echo "FAIL: $*"; exit 1; }
for variable in JAMSIM_READ_DEADLINE_SECONDS JAMSIM_WRITE_DEADLINE_SECONDS; do
  for value in abc 5s 0 0.5 1e-300 -5 1e9 inf nan ' 7'; do
    out=$(env "$variable=$value" "$jamsim" models 2>&1) && fail "$variable='$value' was taken"
    rc=$?
    [[ $rc -eq 2 ]] || fail "$variable='$value': exit $rc, expected 2"
    expected="jamsim: $variable = \"$value\" is not allowed: a number of seconds, at least 1 and below 1e9 \\(unset: [0-9]+\\)"
    [[ $out =~ ^$expected$ ]] || fail "$variable='$value': the message was: $out"
  done
  for value in 1 2.5 600 ''; do
    env "$variable=$value" "$jamsim" models > /dev/null || fail "$variable='$value' was refused"
  done
done
echo "ok: the deadline variables"
