#!/bin/sh
# unwind_parallel_file.sh PROG MODE MPIRUN...: see unwind_parallel_file.cpp. Passes when the job
# exits with code 4 within 60 s (a rank left in a collective close would hang it), a rank names
# the injected failure, and out.h5 still holds the earlier file's values (x = 1.0).
set -u
prog=$1; mode=$2; shift 2
dir=$(mktemp -d /tmp/unwind_pf.XXXXXX)
trap 'rm -rf "$dir"' EXIT
timeout -k 5 60 "$@" -np 2 "$prog" "$dir" "$mode" > "$dir/log" 2>&1
rc=$?
cat "$dir/log"
if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then echo "FAIL: the job hung (killed after 60 s)"; exit 1; fi
[ "$rc" -eq 4 ] || { echo "FAIL: exit code $rc, expected 4"; exit 1; }
grep -q "injected failure on rank" "$dir/log" || { echo "FAIL: the failure is not named"; exit 1; }
h5dump -d x -y -o "$dir/x.txt" "$dir/out.h5" > /dev/null || { echo "FAIL: out.h5 is not readable"; exit 1; }
vals=$(tr -s ' ,\n' '\n' < "$dir/x.txt" | grep -v '^$' | sort -u | tr '\n' ' ')
[ "$vals" = "1 " ] || { echo "FAIL: out.h5 does not hold the earlier values (got: $vals)"; exit 1; }
left=$(ls "$dir" | grep -v '^out.h5$' | grep -v '^log$' | grep -v '^x.txt$' || true)
echo "left beside out.h5: ${left:-nothing}"
if [ "$mode" = all ] && [ -n "$left" ]; then echo "FAIL: a temporary file was left"; exit 1; fi
echo "PASS"
