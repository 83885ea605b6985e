#!/bin/sh
# A model's build in its own steps, by instructions (callgrind; deterministic, unlike wall
# time, whose single cold build is dominated by first touches of memory):
# rj_model_create's instructions over one rj_step's, the mean of K steps.
#   sh bench/build_steps.sh                      the example scenes, long single links,
#                                                chains of links (the table in
#                                                docs/performance.md, "A build in its own steps")
#   sh bench/build_steps.sh SCENE.rjs [KEY=VALUE ...]   one scene
# Needs valgrind (apt-get install valgrind); not part of make test.
B=build
mkdir -p $B
${CC:-cc} -std=c99 -O2 -g -I. bench/build_run.c -o $B/build_run -lm || exit 1
one() {
  # $1: a label, $2: steps, the rest: build_run's arguments
  label=$1; k=$2; shift 2
  valgrind --tool=callgrind --callgrind-out-file=$B/build_steps.out $B/build_run "$@" > $B/build_steps.log 2>/dev/null || { echo "$label: failed"; return; }
  callgrind_annotate --inclusive=yes $B/build_steps.out 2>/dev/null |
    awk -v k="$k" -v label="$label" -v run="$(cat $B/build_steps.log)" '
      / [^ ]*:rj_model_create \[/ { v = $1; gsub(",", "", v); c = v }
      / [^ ]*:rj_step \[/ { v = $1; gsub(",", "", v); s = v }
      END { if (s > 0) printf "%-44s %12.0f %10.0f %8.0f   %s\n", label, c, s / k, c / (s / k), run }'
}
printf "%-44s %12s %10s %8s\n" "model" "build (Ir)" "step (Ir)" "steps"
if [ -n "$1" ]; then
  f=$1; shift
  one "$f $*" 200 "$f" 200 "$@"
  exit 0
fi
for f in examples/scenes/*.rjs; do one "$f" 200 "$f" 200; done
for n in 200 2000; do
  one "elastica.rjs, $n elements" 50 examples/scenes/elastica.rjs 50 link.beam.elements=$n
done
for n in 100 1000; do
  one "chain of $n flexible links" 20 --chain $n 0 20
  one "chain of $n rigid links" 20 --chain $n 1 20
  one "chain of $n rigid links, spring + damper" 20 --chain $n 1 20 1.0 1e-4
done
