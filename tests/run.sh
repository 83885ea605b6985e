#!/bin/sh
# Runs every test command given as an argument (each a quoted shell command), shows their
# PASS/FAIL lines, counts them, and ends with one line "N passed, M failed". A command that
# exits non-zero without printing a FAIL line counts as one failure.
pass=0; fail=0
log=$(mktemp)
for cmd in "$@"; do
  echo "== $cmd"
  sh -c "$cmd" >"$log" 2>&1
  rc=$?
  cat "$log"
  p=$(grep -c '^PASS' "$log"); f=$(grep -c '^FAIL' "$log")
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "FAIL $cmd: exit status $rc"; fi
  pass=$((pass + p)); fail=$((fail + f))
done
rm -f "$log"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
