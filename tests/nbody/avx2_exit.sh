#!/usr/bin/env bash
# An AVX2 build of ssdem-grav on a CPU without AVX2 (label unit; SUITE_SIMD AVX2 builds on x86-64):
# run under qemu-user as a Westmere (SSE4.2, no AVX), it must stop with exit 4 and the message
# naming the fix (cmake -DSUITE_SIMD=baseline), not die on SIGILL in the contact kernel; as a
# Haswell (AVX2) the same binary runs a small scene to the end (the emulation itself is sound).
# Usage: avx2_exit.sh <qemu-x86_64> <ssdem-grav> <two_bodies.toml>
set -uo pipefail
qemu=$1 exe=$2 scene=$3
w=$(mktemp -d "${TMPDIR:-/tmp}/avx2_exit.XXXXXX")
trap 'rm -rf "$w"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
"$qemu" -cpu Westmere "$exe" --scene "$scene" --quiet --set time.end=0.5 --set "output.directory=\"$w/old\"" \
  >"$w/old.log" 2>&1
rc=$?
[ "$rc" -eq 4 ] || fail "without AVX2: exit $rc, expected 4 ($(tail -2 "$w/old.log"))"
grep -q "this CPU has no AVX2; rebuild with cmake -DSUITE_SIMD=baseline" "$w/old.log" || fail "without AVX2: no message naming the fix"
[ ! -e "$w/old" ] || fail "without AVX2: an output directory was made"
"$qemu" -cpu Haswell "$exe" --scene "$scene" --quiet --set time.end=0.5 --set "output.directory=\"$w/new\"" \
  >"$w/new.log" 2>&1 || fail "with AVX2 (Haswell): exit $? ($(tail -2 "$w/new.log"))"
[ -f "$w/new/checkpoint.h5" ] || fail "with AVX2 (Haswell): no checkpoint"
echo "no AVX2: exit 4 with the fix named; AVX2: the run completes"
