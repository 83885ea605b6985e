#!/bin/sh
# rj sweep: a tolerance study of the rigid two-link deployment latches in every sample and
# at every corner, on 1 and 2 threads alike; its scene file is build/deploy's rigid model
# and its preload handle moves the springs' free angles. Then shards under GNU parallel,
# and the designs: normal draws, --lhs, --grid, unit words, --shard auto.
B=${1:-build}; T=$B/sweep_out; mkdir -p $T
# ---- the deployment with rigid links (examples/scenes/deploy_rigid.rjs), 8 s a sample
# (both joints lock by 4.6 s; 8000 steps of 1 ms, about 3 ms a sample)
D=examples/scenes/deploy_rigid.rjs
# the file is build/deploy --links rigid --paper's model: the same angles at every 1 ms row
# (deploy's q2 is j2's theta less 180 deg; deploy prints 10 digits)
$B/deploy --links rigid --paper --t-end 8 --csv $T/dr_deploy.csv 2>/dev/null
$B/rj run $D --t-end 8 --csv $T/dr_rj.csv 2>/dev/null
dq=$(paste -d, $T/dr_deploy.csv $T/dr_rj.csv | awk -F, 'NR == 1 { for (i = 11; i <= NF; i++) c[$i] = i; next }
  { d1 = $2 - $c["j1.theta_deg"]; d2 = $3 + 180 - $c["j2.theta_deg"]; if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2
    if (d1 > m) m = d1; if (d2 > m) m = d2; if ($1 != $11) bad++; n++ }
  END { if (n != 8001 || bad || !(m < 1e-6)) print "FAIL " n " rows, " bad + 0 " times differ, largest |dq| " m " deg"; else print m + 0 }')
case "$dq" in FAIL*) echo "FAIL sweep: deploy_rigid.rjs against build/deploy --links rigid --paper: ${dq#FAIL }";;
  *) echo "PASS sweep: deploy_rigid.rjs is build/deploy --links rigid --paper's model: 8001 rows, angles within $dq deg";; esac
# The tolerances, each uniform and independent about the file's value:
#   friction  +-20 %: j1 0.03825 N m -> 0.0306:0.0459, j2 0.0225 N m -> 0.018:0.027
#   preload   +-5 deg of each spring's free angle, as the file's torque actuators preload1
#             and preload2 at k x 5 deg: 0.0789 and 0.0768 N m/rad x 0.0872665 rad =
#             0.0068853 and 0.0067021 N m (a check below reruns samples with the free
#             angles moved instead)
#   tip mass  +-10 %: arm1 1.2 kg -> 1.08:1.32, arm2 0.336 kg -> 0.3024:0.3696
TOL="--vary joint.j1.friction=0.0306:0.0459 --vary joint.j2.friction=0.018:0.027
  --vary actuator.preload1.torque=-0.0068853:0.0068853 --vary actuator.preload2.torque=-0.0067021:0.0067021
  --vary link.arm1.tip_mass=1.08:1.32 --vary link.arm2.tip_mass=0.3024:0.3696 --t-end 8"
$B/rj sweep $D $TOL --samples 100 --threads 1 --csv $T/tol1.csv 2>/dev/null; st1=$?
$B/rj sweep $D $TOL --samples 100 --threads 2 --csv $T/tol2.csv 2>/dev/null; st2=$?
$B/rj sweep $D $TOL --grid 2 --threads 2 --csv $T/corners.csv 2>/dev/null; st3=$?
# every row ok, both joints locked, its values within the ranges; the lock times' spread
latched() { # csv: "rows bad j1-min j1-max j2-min j2-max"
  awk -F, 'BEGIN { split("0.0306 0.018 -0.0068853 -0.0067021 1.08 0.3024", lo, " ")
                   split("0.0459 0.027 0.0068853 0.0067021 1.32 0.3696", hi, " ") }
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { a = $c["j1.lock"]; b = $c["j2.lock"]; n++
      if ($c["status"] != "ok" || !(a > 0) || !(b > 0)) bad++
      for (i = 1; i <= 6; i++) if ($(i + 1) < lo[i] || $(i + 1) > hi[i]) bad++
      if (n == 1 || a < a0) a0 = a; if (a > a1) a1 = a; if (n == 1 || b < b0) b0 = b; if (b > b1) b1 = b }
    END { printf "%d %d %s %s %s %s", n, bad, a0, a1, b0, b1 }' "$1"
}
set -- $(latched $T/tol1.csv)
if [ $st1 = 0 ] && [ "$1" = 100 ] && [ "$2" = 0 ] && awk "BEGIN { exit !($4 - $3 > 0.2 && $6 - $5 > 0.1) }"; then
  echo "PASS sweep: rigid deployment, 100 samples (friction +-20 %, preload +-5 deg, tip mass +-10 %): every one locks both joints (j1 $3..$4 s, j2 $5..$6 s)"
else echo "FAIL sweep: rigid deployment tolerance study: status $st1, $1 rows, $2 not ok, unlocked or out of range (j1 $3..$4 s, j2 $5..$6 s)"; fi
set -- $(latched $T/corners.csv)
if [ $st3 = 0 ] && [ "$1" = 64 ] && [ "$2" = 0 ]; then
  echo "PASS sweep: rigid deployment, --grid 2: all 64 corners of the tolerance box lock both joints (j1 $3..$4 s, j2 $5..$6 s)"
else echo "FAIL sweep: rigid deployment corners: status $st3, $1 rows, $2 not ok, unlocked or out of range"; fi
if [ $st2 = 0 ] && [ -s $T/tol1.csv ] && cmp -s $T/tol1.csv $T/tol2.csv; then
  echo "PASS sweep: the rigid deployment's study on 1 and 2 threads gives identical rows"
else echo "FAIL sweep: --threads 2 changes the rigid deployment's rows (status $st2)"; fi
# the preload handle: samples 0..2 rerun by rj run with the actuators at 0 and each
# spring's free angle moved by torque / k (300 and 120 deg in the file) lock at the rows'
# times, with their peak pin forces (rj run prints 4 digits)
same=0
for k in 0 1 2; do
  set -- $(awk -F, -v k=$k '$1 == k { pi = atan2(0, -1)
    printf "%s %s %.17g %.17g %s %s %s %s %s %s", $2, $3, 300 + $4 / 0.0789 * 180 / pi, 120 + $5 / 0.0768 * 180 / pi, $6, $7, $9, $10, $12, $13 }' $T/tol1.csv)
  $B/rj run $D --t-end 8 --set joint.j1.friction=$1 --set joint.j2.friction=$2 --set "joint.j1.spring=0.0789 $3 deg" \
    --set "joint.j2.spring=0.0768 $4 deg" --set link.arm1.tip_mass=$5 --set link.arm2.tip_mass=$6 --csv /dev/null 2>$T/pre$k.err
  l1=$(sed -n 's/^rj run: j1: first contact [^ ]* s, lock \([^ ]*\) s.*peak |pin force| \([^ ]*\) N.*/\1 \2/p' $T/pre$k.err)
  l2=$(sed -n 's/^rj run: j2: first contact [^ ]* s, lock \([^ ]*\) s.*peak |pin force| \([^ ]*\) N.*/\1 \2/p' $T/pre$k.err)
  awk -v r="$7 $8 $9 ${10}" -v s="$l1 $l2" 'BEGIN { split(r, a, " "); split(s, b, " ")
    exit !(a[1] > 0 && a[1] == b[1] && a[3] == b[3] && (a[2] - b[2]) ^ 2 < (1e-3 * a[2]) ^ 2 && (a[4] - b[4]) ^ 2 < (1e-3 * a[4]) ^ 2) }' \
    && same=$((same + 1))
done
if [ $same = 3 ]; then echo "PASS sweep: deploy_rigid.rjs's preload actuators: 3 samples rerun with the springs' free angles moved instead lock at the same times, the same pin forces"
else echo "FAIL sweep: preload as a torque differs from the free angle moved: $same of 3 samples agree (last: row $7 $8 $9 ${10}, rj run $l1 $l2)"; fi
# the usage is printed with fputs: a percent sign is written as one
if $B/rj sweep --help | grep -q 'only the samples k with k % n == i' && ! $B/rj sweep --help | grep -q '%%'; then
  echo "PASS sweep: rj sweep --help prints '%', not '%%'"
else echo "FAIL sweep: rj sweep --help: $($B/rj sweep --help | grep '%' | head -2)"; fi
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
