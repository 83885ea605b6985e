#!/bin/sh
# docs/tutorial.md, run as a reader would: in a fresh folder holding the header, build/rj
# and a Makefile stand-in, every file the tutorial says to save ("save this as `PATH`:"
# before a fenced block) is written, then every ```sh block runs in order. Then what the
# text claims is checked against what the runs wrote.
B=${1:-build}
R=$(pwd)
case "$B" in /*) W=$B/tutorial_run ;; *) W=$R/$B/tutorial_run ;; esac
rm -rf "$W" && mkdir -p "$W/build" "$W/mine" || exit 1
cp revjoint.h "$W/" && cp "$B/rj" "$W/build/" || { echo "FAIL tutorial: cannot set up $W"; exit 0; }
printf 'all:\n\t@true\n' > "$W/Makefile"   # `make` is the reader's build; rj is built already
awk -v dir="$W" '
  /[Ss]ave this as `/ { s = $0; sub(/.*[Ss]ave this as `/, "", s); sub(/`.*/, "", s); file = s; next }
  /^```/ && !on { on = 1; lang = substr($0, 4); if (file != "") { out = dir "/" file; printf "" > out } ; next }
  /^```/ && on { on = 0; if (file != "") close(out); file = ""; if (lang == "sh") print "" >> (dir "/steps.sh"); next }
  on && file != "" { print >> out; next }
  on && lang == "sh" { print >> (dir "/steps.sh") }
' docs/tutorial.md
n_files=$(ls "$W/mine" | wc -l)
if (cd "$W" && sh -e steps.sh > steps.out 2> steps.err); then
  echo "PASS tutorial: its commands run in a fresh folder ($n_files files saved from the text, $(grep -c . "$W/steps.sh") command lines)"
else
  echo "FAIL tutorial: a command failed: $(tail -3 "$W/steps.err")"
fi
# the claims: every hinge latches; the outer hinge first, the hub hinge last
lock() { grep "$1: first contact" "$2" | sed 's/.*, lock \([0-9.]*\) s.*/\1/'; }
l1=$(lock h1 "$W/mine/events.txt"); l2=$(lock h2 "$W/mine/events.txt"); l3=$(lock h3 "$W/mine/events.txt")
if [ -n "$l1" ] && [ -n "$l2" ] && [ -n "$l3" ] && awk -v a="$l3" -v b="$l2" -v c="$l1" 'BEGIN { exit !(a < b && b < c) }'; then
  echo "PASS tutorial: all three hinges latch, outer first (h3 $l3 s, h2 $l2 s, h1 $l1 s)"
else
  echo "FAIL tutorial: latch times h1 '$l1' h2 '$l2' h3 '$l3' s"
fi
# the C program prints the same latch times as rj run (to the 4 decimals it prints)
c1=$(grep '^h1:' "$W/steps.out" | sed 's/.*latched at \([0-9.]*\) s/\1/')
r1=$(printf '%.4f' "$l1" 2>/dev/null)
if [ -n "$c1" ] && [ "$c1" = "$r1" ]; then echo "PASS tutorial: the C program's h1 latch time equals rj run's ($c1 s)"
else echo "FAIL tutorial: C program h1 '$c1' s, rj run '$r1' s"; fi
# the sweep: the outer hinge latches later as friction rises, and at 0.8 N m none moves
s1=$(lock h3 "$W/mine/sweep_f0.02.txt"); s2=$(lock h3 "$W/mine/sweep_f0.2.txt"); s3=$(lock h3 "$W/mine/sweep_f0.5.txt")
none=$(grep -c ': first contact none, lock none' "$W/mine/sweep_f0.8.txt")
if [ -n "$s1" ] && [ -n "$s2" ] && [ -n "$s3" ] && awk -v a="$s1" -v b="$s2" -v c="$s3" 'BEGIN { exit !(a < b && b < c) }' && [ "$none" -eq 3 ]; then
  echo "PASS tutorial: the sweep's outer latch comes later with friction (h3 $s1, $s2, $s3 s at 0.02, 0.2, 0.5 N m) and no hinge moves at 0.8 N m"
else
  echo "FAIL tutorial: sweep h3 '$s1' '$s2' '$s3' s at 0.02, 0.2, 0.5 N m; hinges without contact at 0.8 N m: $none of 3"
fi
for f in angles.png torques.png frames/frame_00000.png array.csv; do
  [ -s "$W/mine/$f" ] || echo "FAIL tutorial: mine/$f was not written"
done
