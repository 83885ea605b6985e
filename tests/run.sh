#!/bin/sh
# Runs every test command given as an argument (each a quoted shell command), counts its
# PASS/FAIL lines, and ends with one line "N passed, M failed". A command that exits
# non-zero without printing a FAIL line counts as one failure.
#
# RJT_JOBS commands run at once (default: the machine's processors). With one job each
# command's output streams as it runs; with more, a command's output is printed whole when
# it ends, after a line that says how long it took, and a line when it starts, so that a
# long test is never silent. The tests write to separate files, so they may overlap.
jobs=${RJT_JOBS:-$(nproc 2>/dev/null || echo 1)}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT INT TERM
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# one command: its output to k.log, its exit status to k.rc, its seconds to k.time
run_one() {
  k=$1; shift
  t0=$(now)
  if [ "$jobs" -le 1 ]; then
    { sh -c "$1" 2>&1; echo $? > "$dir/$k.rc"; } | tee "$dir/$k.log"
  else
    sh -c "$1" > "$dir/$k.log" 2>&1; echo $? > "$dir/$k.rc"
  fi
  elapsed "$t0" "$(now)" > "$dir/$k.time"
}

# the tally of one finished command, its output first when it was not streamed
report() {
  k=$1; cmd=$2
  rc=$(cat "$dir/$k.rc")
  if [ "$jobs" -gt 1 ]; then
    echo "== $cmd ($(cat "$dir/$k.time") s)"
    cat "$dir/$k.log"
  else
    echo "-- $cmd: $(cat "$dir/$k.time") s"
  fi
  p=$(grep -c '^PASS' "$dir/$k.log"); f=$(grep -c '^FAIL' "$dir/$k.log")
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "FAIL $cmd: exit status $rc"; fi
  echo "$p $f" > "$dir/$k.count"
}

start=$(now)
k=0
for cmd in "$@"; do
  k=$((k + 1))
  if [ "$jobs" -le 1 ]; then
    echo "== $cmd"
    run_one $k "$cmd"
    report $k "$cmd"
    continue
  fi
  # at most $jobs at once: wait for the oldest running one to end
  while [ "$(ls "$dir" | grep -c '\.running$')" -ge "$jobs" ]; do sleep 0.2; done
  echo "-- started: $cmd"
  touch "$dir/$k.running"
  (
    run_one $k "$cmd"
    # one report at a time: a directory is made atomically
    while ! mkdir "$dir/lock" 2>/dev/null; do sleep 0.1; done
    report $k "$cmd"
    rmdir "$dir/lock"
    rm -f "$dir/$k.running"
  ) &
done
wait
pass=0; fail=0
for count in "$dir"/*.count; do
  read p f < "$count"
  pass=$((pass + p)); fail=$((fail + f))
done
[ "$(ls "$dir" | grep -c '\.count$')" -eq $# ] || { echo "FAIL tests/run.sh: a command left no count"; fail=$((fail + 1)); }
echo "tests: $(elapsed "$start" "$(now)") s wall, $jobs at once"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
