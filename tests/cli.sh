#!/bin/sh
# Example programs: unknown options and malformed values print usage and exit with status 2;
# outputs that cannot be written, and frames folders, fail with status 1 and say why; runs
# that would not end are refused (status 2) unless --force.
B=${1:-build}
T=$B/cli_out
rm -rf "$T"
mkdir -p "$T"
AB=$(cd "$B" && pwd)
# the checks of runs that must be refused get this many seconds: without the refusal they
# would run for hours, and a check must fail rather than hang
TO="timeout 60"
P=cli
. tests/checks.sh
t 2 "impact rejects an unknown option" $B/impact --bogus
t 2 "impact rejects a malformed number" $B/impact --dt 1e-6x
t 2 "impact rejects a negative step" $B/impact --dt -1e-6
t 2 "impact rejects an unknown method" $B/impact --method magic
t 2 "impact rejects NaN" $B/impact --K nan
t 2 "deploy rejects zero elements" $B/deploy --elements 0
t 2 "deploy rejects a missing value" $B/deploy --dt
t 2 "deploy --links pieces rejects more than 100 pieces per link" $B/deploy --links pieces --elements 101
t 2 "deploy --links pieces rejects --method (its latches are momentum)" $B/deploy --links pieces --method adaptive
ok "pd_arm: the PD controller swings the flexible arm to within 0.5 deg of 90 deg in 4 s, its work in the balance" \
  "$B/pd_arm --csv /dev/null 2>&1 | awk '/the arm at/ { a = \$5 - 90; if (a < 0) a = -a; b = \$(NF - 1); if (b < 0) b = -b; exit !(a < 0.5 && b < 1e-6) } END { if (NR == 0) exit 1 }'"
t 2 "pd_arm rejects an unknown option" $B/pd_arm --bogus
t 2 "animate rejects an unknown scene" $B/animate --scene nowhere
t 1 "impact refuses a step above the stability bound (clear error, status 1)" $B/impact --dt 15e-6

# strict parsing: nothing trailing, no blanks, integers as decimal digits, no option taken as a value
t 2 "studies rejects an unknown option" $B/studies --bogus
t 2 "studies rejects a stray argument" $B/studies now
t 2 "animate rejects --size with trailing text" $B/animate --size 640x480junk --t-end 0 --out $T/junk
t 2 "animate rejects --size with a sign" $B/animate --size 640x-480 --t-end 0 --out $T/junk
t 2 "animate rejects --size without a height" $B/animate --size 640x --t-end 0 --out $T/junk
RS="$B/rj sweep examples/scenes/deploy_rigid.rjs --vary joint.j1.friction=0.0306:0.0459"
t 2 "rj sweep rejects --shard with trailing text" $RS --shard 0/3x --samples 1 --t-end 0
t 2 "rj sweep rejects a fractional --seed" $RS --seed 1.5 --samples 1 --t-end 0
t 2 "rj sweep rejects a hex --seed" $RS --seed 0x10 --samples 1 --t-end 0
t 2 "impact rejects a hex integer" $B/impact --elements 0x10 --t-end 0
t 2 "impact rejects a fractional integer" $B/impact --elements 10.5 --t-end 0
t 2 "impact rejects a number with a leading blank" $B/impact --dt " 1e-6" --t-end 0
t 2 "deploy rejects an option where a file name belongs" sh -c "cd $T && $AB/deploy --csv --rigid --t-end 0"

# frames folders: the whole path is made, an earlier run's frames (only those) go first
ok "animate creates a frames folder three levels deep" \
  "$B/animate --t-end 0 --out $T/a/b/c 2>/dev/null && test -f $T/a/b/c/frame_00000.png"
# the view aids: every flag together on a scene file with a title, and the same frame
# without them differs (the aids draw something)
ok "animate --legend --labels --band --separate on solar_array.rjs writes a frame that differs from the plain one" \
  "$B/animate --scene examples/scenes/solar_array.rjs --t-end 0 --out $T/aids_on --legend --labels --band --separate 2>/dev/null \
   && $B/animate --scene examples/scenes/solar_array.rjs --t-end 0 --out $T/aids_off 2>/dev/null \
   && ! cmp -s $T/aids_on/frame_00000.png $T/aids_off/frame_00000.png"
mkdir -p $T/old
for f in frame_00007.png frame_123456.png frame_00001.png.bak frame_1.png frame_000001.png notes.txt; do : > $T/old/$f; done
echo keep > $T/keep.txt
ln -s ../keep.txt $T/old/frame_00009.png
ok "animate removes an earlier run's frame_NNNNN.png files (a link, not its target) and nothing else" \
  "$B/animate --t-end 0 --out $T/old 2>/dev/null && test -f $T/old/frame_00000.png && test ! -e $T/old/frame_00007.png \
   && test ! -e $T/old/frame_123456.png && test ! -L $T/old/frame_00009.png && grep -q keep $T/keep.txt \
   && test -f $T/old/frame_00001.png.bak && test -f $T/old/frame_1.png \
   && test -f $T/old/frame_000001.png && test -f $T/old/notes.txt"
: > $T/plain
m 1 "$T/plain.*Not a directory" "animate fails naming the path when the folder cannot be made" \
  $B/animate --t-end 0 --out $T/plain/sub
mkdir -p $T/blocked/frame_00000.png
m 1 "$T/blocked/frame_00000.png.*Is a directory" "animate fails naming the frame it cannot write" \
  $B/animate --t-end 0 --out $T/blocked
mkdir -p $T/dold
: > $T/dold/frame_00042.png
ok "deploy --frames creates a nested folder and removes an earlier run's frames" \
  "$B/deploy --t-end 0 --csv /dev/null --frames $T/dold/x/y 2>/dev/null && test -f $T/dold/x/y/frame_00000.png \
   && $B/deploy --t-end 0 --csv /dev/null --frames $T/dold 2>/dev/null && test ! -e $T/dold/frame_00042.png"
m 1 "$T/blocked/frame_00000.png.*Is a directory" "deploy --frames fails naming the frame it cannot write" \
  $B/deploy --t-end 0 --csv /dev/null --frames $T/blocked

# a full disk: every program that writes says so and exits 1
if [ -w /dev/full ]; then
  m 1 "/dev/full: No space left" "deploy --csv /dev/full fails" $B/deploy --t-end 1 --csv /dev/full
  m 1 "/dev/full: No space left" "deploy --rigid --csv /dev/full fails" $B/deploy --rigid --t-end 1 --csv /dev/full
  m 1 "standard output: No space left" "deploy > /dev/full fails" sh -c "$B/deploy --t-end 1 > /dev/full"
  m 1 "/dev/full: No space left" "impact --csv /dev/full fails" $B/impact --t-end 0.005 --csv /dev/full
  m 1 "standard output: No space left" "impact > /dev/full fails" sh -c "$B/impact --t-end 0.005 > /dev/full"
  m 1 "standard output: No space left" "impact --all > /dev/full fails" sh -c "$B/impact --all --t-end 0.0001 > /dev/full"
  m 1 "cannot write /dev/full: No space left" "rj sweep --csv /dev/full fails" $RS --samples 2 --t-end 0.1 --csv /dev/full
  m 1 "cannot write standard output: No space left" "rj sweep > /dev/full fails" sh -c "$RS --samples 2 --t-end 0.1 > /dev/full"
  m 1 "stdout: No space left" "quickstart > /dev/full fails" sh -c "$B/quickstart > /dev/full"
else
  echo "SKIP cli: no /dev/full here: the full-disk checks did not run"
fi

# runs that would not end: refused with the estimate unless --force
m 2 "5e\+10 steps.*dt 1e-12 s.*--force" "impact --dt 1e-12 is refused with the step count" $TO $B/impact --dt 1e-12
m 0 "dt 1e-12 s" "impact --dt 1e-12 --force runs (t-end 1e-10 s)" $TO $B/impact --dt 1e-12 --force --t-end 1e-10
m 2 "steps.*--force" "impact --all --dt 1e-12 is refused" $TO $B/impact --all --dt 1e-12
m 2 "e\+15 steps.*dt 3.64e-15 s.*--force" "deploy --method penalty --K 1e22 (dt about 3.6e-15 s) is refused with its step count" \
  $TO $B/deploy --method penalty --K 1e22
m 1 "no usable step.*joints\[1\].*penalty K 1e\+30" "deploy --method penalty --K 1e30 (a bound below 1e-15 s) is refused by the library, naming the joint" \
  $TO $B/deploy --method penalty --K 1e30
m 2 "about 1.33e\+09 steps.*dt 7.5e-06 s.*--force" "rj sweep deploy.rjs --t-end 1e4 (1.3e9 steps a sample at the file's step) is refused" \
  $TO $B/rj sweep examples/scenes/deploy.rjs --vary joint.j1.friction=0.0306:0.0459 --samples 1 --t-end 1e4
m 2 "option --vary solver.dt=7.5e-8:7.5e-6: at LO: about 1.33e\+09 steps.*--force" \
  "rj sweep --vary solver.dt=7.5e-8:7.5e-6 --t-end 100 (1.3e9 steps a sample at LO) is refused" \
  $TO $B/rj sweep examples/scenes/deploy.rjs --vary solver.dt=7.5e-8:7.5e-6 --samples 1 --t-end 100
m 2 "steps.*--force" "animate --t-end 1e6 is refused" $TO $B/animate --t-end 1e6 --out $T/long
m 2 "frames.*--force" "animate --scene impact --fps 1e6 --t-end 1 (400 000 frames) is refused" \
  $TO $B/animate --scene impact --fps 1e6 --t-end 1 --out $T/long
m 2 "steps.*--force" "animate --scene FILE.rjs --t-end 1e6 is refused before its view pass" \
  $TO $B/animate --scene examples/scenes/deploy.rjs --t-end 1e6 --out $T/long
