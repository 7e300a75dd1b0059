#!/bin/sh
# usage: expect_exit.sh <expected exit code> <command...>: succeed iff the command exits with it.
expected=$1
shift
"$@"
rc=$?
if [ "$rc" -ne "$expected" ]; then
  echo "expected exit code $expected, got $rc" >&2
  exit 1
fi
exit 0
