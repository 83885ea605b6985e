#!/bin/sh
# Interleaved A/B wall times: the header at git revision REV against the working tree's, on
# the same programs (bench/paper_run.c), alternating old and new run by run so that both see
# the same machine phases (this VM's speed swings by 2x within minutes). Prints each case's
# median wall time over N pairs and the median of the per-pair ratios old / new.
#   sh bench/ab.sh REV [N]        N pairs (default 9); needs git, and REV must have
#                                 bench/paper_run.c (the new one gets solver.energy_every too)
REV=${1:?usage: sh bench/ab.sh REV [N]}; N=${2:-9}
B=build/ab
mkdir -p $B/old/bench $B/old/examples || exit 1
git show "$REV:revjoint.h" > $B/old/revjoint.h || exit 1
git show "$REV:bench/paper_run.c" > $B/old/bench/paper_run.c || exit 1
git show "$REV:examples/scenes.h" > $B/old/examples/scenes.h || exit 1
F="-std=c99 -O2 -ffp-contract=off"
${CC:-cc} $F -I$B/old $B/old/bench/paper_run.c -o $B/old_run -lm || exit 1
${CC:-cc} $F -I. bench/paper_run.c -o $B/new_run -lm || exit 1
now() { date +%s.%N; }
for args in "6" "--free 2000 20000" "--free 20 1000000"; do
  for ee in 1 16; do
    a2="$args"; [ "$ee" = 1 ] || a2="$args $ee"
    : > $B/t.txt
    i=0
    while [ $i -lt "$N" ]; do
      s=$(now); $B/old_run $args >/dev/null || exit 1; e=$(now); to=$(awk -v s="$s" -v e="$e" "BEGIN { print e - s }")
      s=$(now); $B/new_run $a2 >/dev/null || exit 1; e=$(now); tn=$(awk -v s="$s" -v e="$e" "BEGIN { print e - s }")
      echo "$to $tn" >> $B/t.txt
      i=$((i + 1))
    done
    sort -n -k1 $B/t.txt | awk -v n="$N" 'NR == int((n + 1) / 2) { printf "%s", $1 }' > $B/mo
    sort -n -k2 $B/t.txt | awk -v n="$N" 'NR == int((n + 1) / 2) { printf "%s", $2 }' > $B/mn
    awk '{ print $1 / $2 }' $B/t.txt | sort -n | awk -v n="$N" 'NR == int((n + 1) / 2) { printf "%.2f", $1 }' > $B/mr
    printf "%-22s new with energy_every %-2s  old %7.3f s  new %7.3f s  old/new %sx  (median of %d pairs)\n" "paper_run $args" "$ee" "$(cat $B/mo)" "$(cat $B/mn)" "$(cat $B/mr)" "$N"
  done
done
