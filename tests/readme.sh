#!/bin/sh
# The README's example is examples/quickstart.c, byte for byte, and it builds and runs.
B=${1:-build}
awk '/^```c$/{on=1; next} /^```$/{if(on){exit}} on' README.md > $B/readme_example.c
if cmp -s $B/readme_example.c examples/quickstart.c; then echo "PASS README example is examples/quickstart.c"; else echo "FAIL README example differs from examples/quickstart.c"; fi
out=$($B/quickstart) && echo "$out" | grep -q "joint 1 at" && echo "PASS quickstart runs: $out" || echo "FAIL quickstart: $out"
# The README's scene-file quick start: every `build/rj` line of its shell blocks runs, from a
# copy of the repository's examples in a fresh folder (so out/ does not exist yet), and
# leaves the files it names.
case $B in /*) W=$B/readme_rj ;; *) W=$(pwd)/$B/readme_rj ;; esac
rm -rf $W && mkdir -p $W && cp -r examples $W/ && mkdir -p $W/build && cp $B/rj $W/build/
awk '/^```sh$/{on=1; next} /^```$/{on=0} on && /^build\/rj /' README.md | sed 's/ *#.*$//' > $W/commands.sh
n=$(wc -l < $W/commands.sh)
if [ "$n" -ge 4 ] && (cd $W && sh -e commands.sh >/dev/null 2>$W/stderr.txt) && [ -s $W/out/solar.csv ] && [ -s $W/out/solar_angles.png ] && [ -s $W/out/solar_frames/frame_00000.png ]; then
  echo "PASS README quick start: its $n build/rj commands run in a fresh folder and write out/solar.csv, out/solar_angles.png and out/solar_frames/"
else
  echo "FAIL README quick start: $n build/rj commands; $(tail -2 $W/stderr.txt 2>/dev/null)"
fi
