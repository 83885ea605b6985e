#!/bin/sh
# The step's vector lanes against its scalar code (tests/test_lanes.c): the default build
# (on x86-64 Linux with gcc: AVX2 clones of the lane kernels where the CPU has AVX2), the
# baseline lanes alone (-DRJ_NO_CLONES), a -O3 -march=native build and a -DRJ_NO_SIMD build
# must print the same state hashes.
B=${1:-build}
CC=${CC:-cc}
F="-std=c99 -Wall -Wextra -pedantic -Werror -ffp-contract=off -I."
rc=0
$CC $F -O2 tests/test_lanes.c -o $B/lanes_vec -lm || rc=1
$CC $F -O2 -DRJ_NO_CLONES tests/test_lanes.c -o $B/lanes_base -lm || rc=1
$CC $F -O2 -DRJ_NO_SIMD tests/test_lanes.c -o $B/lanes_scalar -lm || rc=1
$CC $F -O3 -march=native tests/test_lanes.c -o $B/lanes_native -lm || rc=1
[ $rc = 0 ] || { echo "FAIL lanes: build"; exit 1; }
$B/lanes_vec > $B/lanes_vec.txt || rc=1
$B/lanes_base > $B/lanes_base.txt || rc=1
$B/lanes_scalar > $B/lanes_scalar.txt || rc=1
$B/lanes_native > $B/lanes_native.txt || rc=1
n=$(wc -l < $B/lanes_scalar.txt)
if [ $rc = 0 ] && [ "$n" -ge 30 ] && cmp -s $B/lanes_vec.txt $B/lanes_scalar.txt && cmp -s $B/lanes_base.txt $B/lanes_scalar.txt && cmp -s $B/lanes_native.txt $B/lanes_scalar.txt; then
  echo "PASS lanes: $n scenes, the same state hash from vector lanes (-O2 default, -O2 baseline lanes, -O3 -march=native) and scalar code (RJ_NO_SIMD)"
else
  echo "FAIL lanes: the vector and scalar builds differ (or a run failed):"
  diff $B/lanes_scalar.txt $B/lanes_vec.txt; diff $B/lanes_scalar.txt $B/lanes_base.txt; diff $B/lanes_scalar.txt $B/lanes_native.txt
  exit 1
fi
