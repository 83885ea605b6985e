#!/bin/sh
# Golden histories: reruns both benchmark programs at their defaults (impact: every method
# and release rule) and compares with tests/golden/*.csv. "--write" regenerates them.
# Tolerance: |a - g| <= 1e-9 |g| + 1e-9 x (column range), flags exact. The spread measured
# between gcc -O0, gcc -O2, gcc -O3 -march=native and clang -O2 (all -std=c99
# -ffp-contract=off) is zero: the files are bit-identical. The tolerance only absorbs libm
# differences of a few ulps on another system.
B=${1:-build}; W=$2
G=tests/golden; T=$B/golden_out
mkdir -p $T $G
rc=0
check() { # name, produced file
  if [ "$W" = "--write" ]; then cp "$2" "$G/$1.csv"; echo "PASS wrote $G/$1.csv"; return; fi
  $B/csvdiff "$G/$1.csv" "$2" --rel 1e-9 --abs 1e-9 --exact flag --exact flag1 --exact flag2 || rc=1
}
$B/deploy --paper --csv $T/deploy.csv 2>/dev/null || { echo "FAIL deploy run"; rc=1; }
check deploy $T/deploy.csv
if [ "$W" != "--write" ]; then
  $B/deploy --scene examples/scenes/deploy.rjs --csv $T/deploy_scene.csv 2>/dev/null || { echo "FAIL deploy --scene run"; rc=1; }
  check deploy $T/deploy_scene.csv
  # build/deploy takes the energy accounts every 16th step: the history must not depend on it
  $B/deploy --paper --energy-every 1 --csv $T/deploy_k1.csv 2>/dev/null || { echo "FAIL deploy --energy-every 1 run"; rc=1; }
  if cmp -s $T/deploy.csv $T/deploy_k1.csv; then echo "PASS deploy: the same history byte for byte with the energy accounts every step (--energy-every 1) as every 16th (the default)"
  else echo "FAIL deploy: --energy-every 1 changed the history"; rc=1; fi
fi
$B/deploy --rigid --csv $T/deploy_rigid.csv 2>/dev/null || { echo "FAIL deploy --rigid run"; rc=1; }
check deploy_rigid $T/deploy_rigid.csv
for m in penalty adaptive momentum forced energy; do
  for r in rc12 rc13; do
    $B/impact --method $m --release $r --csv $T/impact_${m}_$r.csv 2>/dev/null || { echo "FAIL impact $m $r run"; rc=1; }
    check impact_${m}_$r $T/impact_${m}_$r.csv
  done
done
exit $rc
