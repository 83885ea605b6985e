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


# ---- rj sweep's designs: normal draws, --lhs, --grid, unit words, --shard auto from any
# first id. Most runs use --t-end 0 (the scene loaded and built, no step): the values
# columns are what these check.
SA=examples/scenes/solar_array.rjs
R="$B/rj sweep $SA"
# a normal: 400 draws' mean and standard deviation within 4 standard errors of MEAN and
# SD (SE of the mean SD/sqrt(n), of the SD about SD/sqrt(2n)), and the share within 1 SD
# within 4 of its standard errors of 68.27 %
$R --vary joint.h1.friction=normal:0.02:0.002 --samples 400 --t-end 0 --csv $T/normal.csv 2>/dev/null
stats=$(awk -F, 'NR > 1 { x = $2; n++; s += x; ss += x * x; if (x > 0.018 && x < 0.022) in1++; if ($(NF - 1) != "ok") bad++ }
  END { m = s / n; sd = sqrt((ss - n * m * m) / (n - 1)); p = in1 / n
        ok = n == 400 && !bad && (m - 0.02) ^ 2 < (4 * 0.002 / sqrt(n)) ^ 2 && (sd - 0.002) ^ 2 < (4 * 0.002 / sqrt(2 * n)) ^ 2 \
             && (p - 0.6827) ^ 2 < 16 * 0.6827 * 0.3173 / n
        printf "%d %.6g %.6g %.4f %d", n, m, sd, p, ok }' $T/normal.csv)
set -- $stats
if [ "$5" = 1 ]; then echo "PASS sweep: normal:0.02:0.002, $1 draws: mean $2, SD $3, $4 within 1 SD (each within 4 standard errors)"
else echo "FAIL sweep: normal:0.02:0.002: $stats (n, mean, SD, share within 1 SD, ok)"; fi
# a normal is not cut off: a draw the file refuses (a negative friction) is a failed row
# with the file's message, the sweep goes on, and its exit status is 0
$R --vary joint.h1.friction=normal:0.002:0.01 --samples 20 --t-end 0 --csv $T/normal_bad.csv 2>/dev/null; st=$?
nbad=$(grep -c ',parse,".*friction = -.* is out of range' $T/normal_bad.csv)
nneg=$(awk -F, 'NR > 1 && $2 < 0' $T/normal_bad.csv | wc -l)
if [ $st = 0 ] && [ "$nbad" -gt 0 ] && [ "$nbad" = "$nneg" ] && [ $(wc -l < $T/normal_bad.csv) = 21 ]; then
  echo "PASS sweep: normal draws the file refuses ($nbad of 20 negative frictions) are failed rows with its message"
else echo "FAIL sweep: normal draws refused by the file: status $st, $nbad failed rows, $nneg negative values"; fi
# --lhs: in each key, each of the N strata of equal probability holds one sample: for a
# range floor(N (x - LO) / (HI - LO)), for a normal floor(N Phi((x - MEAN) / SD)), Phi
# from erf (Abramowitz and Stegun 7.1.26, error 1.5e-7; a stratum is 1/N = 0.01 wide)
LHS="--vary joint.h1.friction=0.01:0.03 --vary material.cfrp_sandwich.rho=2250:2750 --vary joint.h1.angle0=normal:90:2deg"
$R $LHS --lhs --samples 100 --t-end 0 --csv $T/lhs.csv 2>/dev/null
strata=$(awk -F, 'function erf(x,  t, y, s) { s = x < 0 ? -1 : 1; x = x < 0 ? -x : x; t = 1 / (1 + 0.3275911 * x)
    y = 1 - ((((1.061405429 * t - 1.453152027) * t + 1.421413741) * t - 0.284496736) * t + 0.254829592) * t * exp(-x * x); return s * y }
  function put(key, s) { if (s < 0 || s >= N || seen[key, s]++) bad++ }
  BEGIN { N = 100 } NR > 1 { n++; put(1, int(N * ($2 - 0.01) / 0.02)); put(2, int(N * ($3 - 2250) / 500))
    put(3, int(N * 0.5 * (1 + erf(($4 - 90) / 2 / sqrt(2))))) }
  END { print n + 0, bad + 0 }' $T/lhs.csv)
if [ "$strata" = "100 0" ] && head -1 $T/lhs.csv | grep -q '^sample,joint.h1.friction,material.cfrp_sandwich.rho,joint.h1.angle0\[deg\],'; then
  echo "PASS sweep: --lhs --samples 100: each of 2 ranges and a normal (in deg) has one sample in each of its 100 strata"
else echo "FAIL sweep: --lhs strata: $strata (rows, strata held twice or outside), header $(head -1 $T/lhs.csv | cut -c1-80)"; fi
# --grid 3 on two keys: 9 rows, the first key slowest, LO, midpoint, HI each; --grid 1:
# the midpoints
$R --vary joint.h1.friction=0.01:0.03 --vary material.cfrp_sandwich.rho=2250:2750 --grid 3 --t-end 0 --csv $T/grid.csv 2>/dev/null
$R --vary joint.h1.friction=0.01:0.03 --vary material.cfrp_sandwich.rho=2250:2750 --grid 1 --t-end 0 --csv $T/grid1.csv 2>/dev/null
if awk -F, 'BEGIN { split("0.01 0.02 0.03", f, " "); split("2250 2500 2750", r, " ") }
    NR > 1 { k = $1; if (k != NR - 2 || $2 != f[int(k / 3) + 1] || $3 != r[k % 3 + 1]) bad++; n++ } END { exit bad || n != 9 }' $T/grid.csv \
   && [ "$(cut -d, -f1-3 $T/grid1.csv | tail -n +2)" = "0,0.02,2500" ]; then
  echo "PASS sweep: --grid 3 on two keys: 9 rows, the 3 x 3 values (0.01 0.02 0.03 by 2250 2500 2750, the last key fastest); --grid 1: the midpoints"
else echo "FAIL sweep: --grid 3: $(cut -d, -f1-3 $T/grid.csv | tr '\n' ' ')"; fi
# shards joined are the unsharded rows byte for byte under --lhs (12 samples, 3 shards)
# and --grid (3 x 3, 4 shards), with short runs; --resume of a cut --lhs file completes it
join_shards() { # out, files...
  out=$1; shift; { head -1 $1; tail -q -n +2 "$@" | sort -t, -k1,1n; } > $out
}
SH="--vary joint.h1.friction=normal:0.02:0.003 --vary material.cfrp_sandwich.rho=2250:2750 --t-end 0.5"
$R $SH --lhs --samples 12 --csv $T/lhs_one.csv 2>/dev/null
for i in 0 1 2; do $R $SH --lhs --samples 12 --shard $i/3 --csv $T/lhs_s$i.csv 2>/dev/null; done
join_shards $T/lhs_join.csv $T/lhs_s0.csv $T/lhs_s1.csv $T/lhs_s2.csv
GR="--vary joint.h1.friction=0.016:0.024 --vary material.cfrp_sandwich.rho=2250:2750 --t-end 0.5 --grid 3"
$R $GR --csv $T/grid_one.csv 2>/dev/null
for i in 0 1 2 3; do $R $GR --shard $i/4 --csv $T/grid_s$i.csv 2>/dev/null; done
join_shards $T/grid_join.csv $T/grid_s0.csv $T/grid_s1.csv $T/grid_s2.csv $T/grid_s3.csv
head -5 $T/lhs_one.csv > $T/lhs_cut.csv
$R $SH --lhs --samples 12 --threads 2 --resume --csv $T/lhs_cut.csv 2>/dev/null
if [ $(wc -l < $T/lhs_one.csv) = 13 ] && cmp -s $T/lhs_one.csv $T/lhs_join.csv && [ $(wc -l < $T/grid_one.csv) = 10 ] \
   && cmp -s $T/grid_one.csv $T/grid_join.csv && cmp -s $T/lhs_one.csv $T/lhs_cut.csv; then
  echo "PASS sweep: shards joined equal one process byte for byte under --lhs (3 shards) and --grid (4 shards); --resume completes a cut --lhs file"
else echo "FAIL sweep: --lhs or --grid shards, or --lhs --resume, differ from one process"; fi
# a unit word: the row holds the angle in deg, and rj run --set 'KEY=VALUE deg' with it
# locks h1 at the same time
$R --vary joint.h1.angle0=85:95deg --grid 2 --t-end 4 --csv $T/unit.csv 2>/dev/null
a=$(sed -n 3p $T/unit.csv | cut -d, -f2); lk=$(sed -n 3p $T/unit.csv | cut -d, -f4)
$B/rj run $SA --t-end 4 --set "joint.h1.angle0=$a deg" --csv /dev/null 2>$T/unit_run.err
lr=$(sed -n 's/^rj run: h1: first contact [^ ]* s, lock \([^ ]*\) s.*/\1/p' $T/unit_run.err)
if [ "$a" = 95 ] && [ -n "$lr" ] && awk "BEGIN { exit !($lk > 0 && ($lk - $lr) ^ 2 < 1e-16) }"; then
  echo "PASS sweep: --vary joint.h1.angle0=85:95deg: the row holds 95 (deg), and rj run --set 'joint.h1.angle0=95 deg' locks h1 at its time ($lk s)"
else echo "FAIL sweep: unit: value '$a', lock $lk, rj run's '$lr'"; fi
# bad designs are refused (status 2), the option and the value named
bad() { # description, pattern, args...
  what=$1; pat=$2; shift 2
  out=$($R "$@" 2>&1 >/dev/null); st=$?
  if [ $st = 2 ] && printf '%s\n' "$out" | grep -Eq -- "$pat"; then echo "PASS sweep: $what (status 2)"
  else echo "FAIL sweep: $what: status $st: $(printf '%s' "$out" | head -1)"; fi
}
V4="--vary joint.h1.friction=0:1 --vary joint.h2.friction=0:1 --vary joint.h3.friction=0:1 --vary joint.h4.friction=0:1"
bad "--grid 1000 on 4 keys (1e12 samples) is refused, the number named" \
  "option --grid 1000: 4 --vary keys make 1000\\^4 = 1e\\+12 samples, more than the 1e9" $V4 --grid 1000
bad "a normal with SD < 0 is refused" "option --vary: bad value 'joint.h1.friction=normal:0.02:-0.001' \\(need SD >= 0" \
  --vary joint.h1.friction=normal:0.02:-0.001 --samples 2
bad "--grid with a normal key is refused, naming it" "option --grid takes LO:HI ranges: --vary joint.h1.friction=normal:0.02:0.001 is a normal" \
  --vary joint.h1.friction=normal:0.02:0.001 --grid 3
bad "--lhs with --grid is refused, naming both" "options --grid and --lhs do not go together" --vary joint.h1.friction=0:1 --grid 3 --lhs
bad "--grid with --samples is refused, naming both" "options --grid and --samples do not go together" --vary joint.h1.friction=0:1 --grid 3 --samples 9
bad "a unit word the key does not take is the file's message" "option --vary joint.h1.friction=0.01:0.03deg: at LO = 0.01 deg: .*without a unit word" \
  --vary joint.h1.friction=0.01:0.03deg --samples 2
bad "a normal whose mean the file refuses is refused" "option --vary joint.h1.friction=normal:-1:0.1: at MEAN = -1: .*out of range" \
  --vary joint.h1.friction=normal:-1:0.1 --samples 2
# --shard auto in an array that starts at 1 (sbatch --array=1-4): tasks 1..4 are 0/4..3/4;
# an array with a step, and an id outside the array, are refused
SL="--vary joint.h1.friction=0.01:0.03 --samples 10 --t-end 0"
same=1
for id in 1 2 3 4; do
  $R $SL --shard $((id - 1))/4 --csv $T/sl_want$id.csv 2>/dev/null
  env SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=4 SLURM_ARRAY_TASK_STEP=1 SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_COUNT=4 \
    $R $SL --shard auto --csv $T/sl_got$id.csv 2>/dev/null || same=0
  cmp -s $T/sl_want$id.csv $T/sl_got$id.csv || same=0
done
[ $same = 1 ] && echo "PASS sweep: --shard auto with SLURM_ARRAY_TASK_MIN=1, ids 1..4 of 4: the files of --shard 0/4 .. 3/4" \
  || echo "FAIL sweep: --shard auto with SLURM_ARRAY_TASK_MIN=1 differs from --shard 0/4 .. 3/4"
out=$(env SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_STEP=2 SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=4 $R $SL --shard auto 2>&1 >/dev/null); st=$?
out2=$(env SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_COUNT=4 $R $SL --shard auto 2>&1 >/dev/null); st2=$?
if [ $st = 2 ] && echo "$out" | grep -q "option --shard auto: SLURM_ARRAY_TASK_STEP=2: the array has a step" && [ $st2 = 2 ] \
   && echo "$out2" | grep -q "option --shard auto: SLURM_ARRAY_TASK_ID=5 less SLURM_ARRAY_TASK_MIN=1 is 4, not in \[0, 3\]"; then
  echo "PASS sweep: --shard auto refuses an array with a step, and an id outside the array, naming the variables"
else echo "FAIL sweep: --shard auto step/range: status $st, $st2: $(echo "$out" | head -1) / $(echo "$out2" | head -1)"; fi
