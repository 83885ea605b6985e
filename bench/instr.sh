#!/bin/sh
# Instructions per step by function, from callgrind at two run lengths so that set-up
# cancels; deterministic, unlike wall time on a shared machine.
#   sh bench/instr.sh [CFLAGS]            the deployment at the paper's settings (0.15 s and
#                                         0.30 s: 20000 steps apart), per step
#   sh bench/instr.sh [CFLAGS] N          one free link of N elements (200 and 400 steps),
#                                         per element-step
#   sh bench/instr.sh CFLAGS N|"" K       either, with solver.energy_every = K
#   sh bench/instr.sh CFLAGS N K P        the free link with solver.in_place = P (0 auto, 1 on, 2 off)
#   sh bench/instr.sh CFLAGS bare|all     the feature-cost scene, bare or "everything on", per step
#   sh bench/instr.sh CFLAGS gravity|torque|nodeforce|load|follower|massdamp|kv
#                                         the same scene with one load feature, or with
#                                         mass_damping or Kelvin-Voigt on both links (paper_run.c)
# CFLAGS default -O2 (valgrind does not run AVX-512 code: not -march=native on such CPUs).
# Needs valgrind (apt-get install valgrind); not part of make test.
F=${1:--O2}; N=$2; EE=${3:-1}; IP=${4:-0}
B=build
mkdir -p $B
${CC:-cc} -std=c99 $F -g -ffp-contract=off -I. bench/paper_run.c -o $B/paper_run -lm || exit 1
F2=
case "$N" in bare) F2=0;; all) F2=1;; gravity) F2=2;; torque) F2=3;; nodeforce) F2=4;; load) F2=5;; follower) F2=6;; massdamp) F2=7;; kv) F2=8;; esac
if [ -n "$F2" ]; then
  A="--two-link $F2 10000"; C="--two-link $F2 20000"; D=10000; U="step, feature scene ($N, BENCHMARKS.md section 5)"
elif [ -n "$N" ]; then A="--free $N 200 $EE $IP"; C="--free $N 400 $EE $IP"; D=$((200 * N)); U="element-step, $N elements"
else A="0.15 $EE"; C="0.30 $EE"; D=20000; U="step, deployment at the paper's settings"; fi
valgrind --tool=callgrind --callgrind-out-file=$B/instr_a.out $B/paper_run $A >/dev/null 2>&1 || exit 1
valgrind --tool=callgrind --callgrind-out-file=$B/instr_b.out $B/paper_run $C >/dev/null 2>&1 || exit 1
for x in a b; do
  callgrind_annotate --inclusive=no --auto=no $B/instr_$x.out 2>/dev/null | grep 'revjoint.h:\|PROGRAM TOTALS' | grep -v '=>' > $B/instr_$x.txt
done
echo "instructions per $U (flags: $F):"
awk -v D=$D 'function key(l){ sub(/^[ 0-9,]+\([ .0-9%]+\) +/, "", l); sub(/ \[.*/, "", l); sub(/.*revjoint.h:/, "", l); return l }
     { v = $1; gsub(",", "", v); k = key($0) }
     FNR == NR { a[k] = v; next }
     { d = (v - a[k]) / D; if (d >= 0.5) printf "  %8.1f  %s\n", d, k }' $B/instr_a.txt $B/instr_b.txt
