#!/bin/sh
# Runs every test command given as an argument (each a quoted shell command), streams its
# output as it runs (a long test is never silent), counts its PASS/FAIL lines, and ends
# with one line "N passed, M failed". A command that exits non-zero without printing a
# FAIL line counts as one failure.
pass=0; fail=0
log=$(mktemp)
rcf=$(mktemp)
for cmd in "$@"; do
  echo "== $cmd"
  # the exit status crosses the pipe through a file: plain sh has no pipefail
  { sh -c "$cmd" 2>&1; echo $? > "$rcf"; } | tee "$log"
  rc=$(cat "$rcf")
  p=$(grep -c '^PASS' "$log"); f=$(grep -c '^FAIL' "$log")
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "FAIL $cmd: exit status $rc"; fi
  pass=$((pass + p)); fail=$((fail + f))
done
rm -f "$log" "$rcf"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
