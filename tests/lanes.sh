#!/bin/sh
# The step's vector lanes against its scalar code (tests/test_lanes.c): the default build
# (on x86-64: the 4-lane AVX2 kernels where the CPU has AVX2), the same build made to take
# its path for CPUs without AVX2 (the scalar loops; __builtin_cpu_supports defined as 0),
# the 2-lane kernels alone (-DRJ_NO_DISPATCH), a -O3 -march=native build, a clang build
# and a -DRJ_NO_SIMD build must print the same state hashes. The native and clang builds
# leave FMA contraction on (gcc GNU mode with -ffp-contract=fast; clang's default,
# contraction within expressions): the header turns it off for its own code.
# Every build runs each scene double-buffered and in place (solver.in_place): a line
# saying "DIFFERS" fails, and most scenes must step in place.
B=${1:-build}
CC=${CC:-cc}
W="-Wall -Wextra -pedantic -Werror -I."
F="-std=c99 $W -ffp-contract=off"
rc=0
$CC $F -O2 tests/test_lanes.c -o $B/lanes_vec -lm || rc=1
$CC $F -O2 '-D__builtin_cpu_supports(x)=0' tests/test_lanes.c -o $B/lanes_fallback -lm || rc=1
$CC $F -O2 -DRJ_NO_DISPATCH tests/test_lanes.c -o $B/lanes_base -lm || rc=1
$CC $F -O2 -DRJ_NO_SIMD tests/test_lanes.c -o $B/lanes_scalar -lm || rc=1
$CC -std=gnu99 $W -O3 -march=native -ffp-contract=fast tests/test_lanes.c -o $B/lanes_native -lm || rc=1
clang -std=gnu99 $W -O2 tests/test_lanes.c -o $B/lanes_clang -lm || rc=1
[ $rc = 0 ] || { echo "FAIL lanes: build"; exit 1; }
$B/lanes_vec > $B/lanes_vec.txt || rc=1
$B/lanes_fallback > $B/lanes_fallback.txt || rc=1
$B/lanes_base > $B/lanes_base.txt || rc=1
$B/lanes_scalar > $B/lanes_scalar.txt || rc=1
$B/lanes_native > $B/lanes_native.txt || rc=1
$B/lanes_clang > $B/lanes_clang.txt || rc=1
n=$(wc -l < $B/lanes_scalar.txt)
ip=$(grep -c "in place same" $B/lanes_scalar.txt)
if grep -q DIFFERS $B/lanes_vec.txt $B/lanes_fallback.txt $B/lanes_base.txt $B/lanes_scalar.txt $B/lanes_native.txt $B/lanes_clang.txt; then
  echo "FAIL lanes: in place and double-buffered steps differ:"; grep DIFFERS $B/lanes_*.txt; exit 1
fi
if [ $rc = 0 ] && [ "$n" -ge 30 ] && [ "$ip" -ge 40 ] && cmp -s $B/lanes_vec.txt $B/lanes_scalar.txt && cmp -s $B/lanes_fallback.txt $B/lanes_scalar.txt && cmp -s $B/lanes_base.txt $B/lanes_scalar.txt && cmp -s $B/lanes_native.txt $B/lanes_scalar.txt && cmp -s $B/lanes_clang.txt $B/lanes_scalar.txt; then
  echo "PASS lanes: $n scenes, the same state hash from vector lanes (gcc -O2 with AVX2 dispatch, the same on its path for CPUs without AVX2, gcc -O2 2-lane only, gcc -std=gnu99 -O3 -march=native -ffp-contract=fast, clang -std=gnu99 -O2) and scalar code (RJ_NO_SIMD); $ip of them also in place, the same bits"
else
  echo "FAIL lanes: the vector and scalar builds differ (or a run failed):"
  diff $B/lanes_scalar.txt $B/lanes_vec.txt; diff $B/lanes_scalar.txt $B/lanes_fallback.txt; diff $B/lanes_scalar.txt $B/lanes_base.txt; diff $B/lanes_scalar.txt $B/lanes_native.txt; diff $B/lanes_scalar.txt $B/lanes_clang.txt
  exit 1
fi
