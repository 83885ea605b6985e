#!/bin/sh
# The README's example is examples/quickstart.c, byte for byte, and it builds and runs.
B=${1:-build}
awk '/^```c$/{on=1; next} /^```$/{if(on){exit}} on' README.md > $B/readme_example.c
if cmp -s $B/readme_example.c examples/quickstart.c; then echo "PASS README example is examples/quickstart.c"; else echo "FAIL README example differs from examples/quickstart.c"; fi
out=$($B/quickstart) && echo "$out" | grep -q "joint 1 at" && echo "PASS quickstart runs: $out" || echo "FAIL quickstart: $out"
