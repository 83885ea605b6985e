#!/bin/sh
# build/sweep: shards concatenate to the unsharded run, threads do not change results, and
# the rigid deployment locks in every sample at +-20 % friction.
B=${1:-build}; T=$B/sweep_out; mkdir -p $T
$B/sweep --samples 24 --threads 1 --csv $T/one.csv 2>/dev/null
$B/sweep --samples 24 --threads 2 --csv $T/two.csv 2>/dev/null
$B/sweep --samples 24 --shard 0/3 --csv $T/s0.csv 2>/dev/null
$B/sweep --samples 24 --shard 1/3 --csv $T/s1.csv 2>/dev/null
$B/sweep --samples 24 --shard 2/3 --csv $T/s2.csv 2>/dev/null
if cmp -s $T/one.csv $T/two.csv; then echo "PASS sweep: 1 and 2 threads give identical rows"; else echo "FAIL sweep: thread count changes the rows"; fi
cat $T/s0.csv $T/s1.csv $T/s2.csv | sort > $T/shards.csv; sort $T/one.csv > $T/one_sorted.csv
if cmp -s $T/shards.csv $T/one_sorted.csv; then echo "PASS sweep: shards 0/3, 1/3, 2/3 together equal the unsharded run"; else echo "FAIL sweep: shards differ from the unsharded run"; fi
f=$(awk -F, 'NR>1 && $10 != 0' $T/one.csv | wc -l)
[ "$f" -eq 0 ] && echo "PASS sweep: every one of 24 samples (friction +-20 %, preload +-5 deg, tip mass +-10 %) locks both joints" || echo "FAIL sweep: $f samples failed to lock"
# progress on standard error (a --grid 50 sweep is 6.25 million samples): with --progress a
# line at the end into a file or pipe, the rows the same as without it
$B/sweep --samples 24 --progress --csv $T/prog.csv 2>$T/prog.err
if grep -Eq '^sweep: 24 / 24 samples \(100.0 %\), [0-9.]+ s, .* samples/s, ETA 0 s$' $T/prog.err && cmp -s $T/prog.csv $T/one.csv; then
  echo "PASS sweep: --progress prints samples done, rate and ETA on standard error; the rows unchanged"
else echo "FAIL sweep: --progress: $(head -c 300 $T/prog.err)"; fi
# the usage is printed with fputs: a percent sign is written as one
if $B/sweep --help | grep -q 'friction varied by +-P % (default 20)' && ! $B/sweep --help | grep -q '%%'; then
  echo "PASS sweep: --help prints '%', not '%%'"
else echo "FAIL sweep: --help: $($B/sweep --help | grep '%' | head -2)"; fi
# a misspelt option gets the nearest one; numbers are decimal
if $B/sweep --samles 3 2>&1 | grep -q "^.*sweep: unknown option '--samles'; did you mean '--samples'?" \
   && $B/sweep --t-end 0x10 2>&1 | grep -q "option --t-end: bad value '0x10' (need a finite decimal number"; then
  echo "PASS sweep: --samles: did you mean '--samples'; --t-end 0x10 (hex) is refused"
else echo "FAIL sweep: no suggestion for --samles, or hex taken as a number"; fi
# rj sweep over any scene: 4 shards run by GNU parallel (a cluster's way to split a study,
# docs/studies.md), joined and sorted by index, are the rows one process writes
V="--vary joint.h1.friction=0.016:0.024 --vary material.cfrp_sandwich.rho=2250:2750 --samples 8 --t-end 3"
$B/rj sweep examples/scenes/solar_array.rjs $V --csv $T/rj_one.csv 2>/dev/null
parallel --will-cite -j 2 "$B/rj sweep examples/scenes/solar_array.rjs $V --shard {}/4 --csv $T/rj_s{}.csv 2>/dev/null" ::: 0 1 2 3
{ head -1 $T/rj_s0.csv; tail -q -n +2 $T/rj_s0.csv $T/rj_s1.csv $T/rj_s2.csv $T/rj_s3.csv | sort -t, -k1,1n; } > $T/rj_joined.csv
if [ -s $T/rj_one.csv ] && [ $(wc -l < $T/rj_one.csv) = 9 ] && cmp -s $T/rj_joined.csv $T/rj_one.csv; then
  echo "PASS sweep: rj sweep in 4 shards run by GNU parallel, joined and sorted, equals one process byte for byte"
else echo "FAIL sweep: rj sweep's shards under GNU parallel differ from one process (or it did not run)"; fi

