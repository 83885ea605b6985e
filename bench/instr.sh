#!/bin/sh
# Instructions per step of the deployment at the paper's settings, by function: callgrind
# on bench/paper_run.c over 0.15 s and 0.30 s (20000 steps apart), so set-up cancels.
# Deterministic, unlike wall time on a shared machine.
#   sh bench/instr.sh [CFLAGS]      (default -O2; valgrind needs it, AVX-512 builds do not run)
F=${1:--O2}
B=build
mkdir -p $B
cc -std=c99 $F -g -ffp-contract=off -I. bench/paper_run.c -o $B/paper_run -lm || exit 1
valgrind --tool=callgrind --callgrind-out-file=$B/instr_a.out $B/paper_run 0.15 >/dev/null 2>&1 || exit 1
valgrind --tool=callgrind --callgrind-out-file=$B/instr_b.out $B/paper_run 0.30 >/dev/null 2>&1 || exit 1
callgrind_annotate --inclusive=no --auto=no $B/instr_a.out 2>/dev/null | grep 'revjoint.h:\|PROGRAM TOTALS' | grep -v '=>' > $B/instr_a.txt
callgrind_annotate --inclusive=no --auto=no $B/instr_b.out 2>/dev/null | grep 'revjoint.h:\|PROGRAM TOTALS' | grep -v '=>' > $B/instr_b.txt
echo "instructions per step (flags: $F), 20000 steps:"
awk 'function key(l){ sub(/^[ 0-9,]+\([ .0-9%]+\) +/, "", l); sub(/ \[.*/, "", l); sub(/.*revjoint.h:/, "", l); return l }
     { v = $1; gsub(",", "", v); k = key($0) }
     FNR == NR { a[k] = v; next }
     { d = (v - a[k]) / 20000; if (d >= 5) printf "  %8.0f  %s\n", d, k }' $B/instr_a.txt $B/instr_b.txt
