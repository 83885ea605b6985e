#!/bin/sh
# build/rj, the scene-file command line: rj run's columns, rows, events and exit statuses,
# its history against build/deploy's, rj check on valid and broken scenes, rj plot's PNG,
# rj animate's frames against build/animate's. One PASS or FAIL line per check.
B=${1:-build}
T=$B/rj_out
S=examples/scenes
rm -rf "$T"
mkdir -p "$T"
AB=$(cd "$B" && pwd)
AT=$(cd "$T" && pwd)
P=rj
. tests/checks.sh
# the header rj run must write for a scene file: its joints' and links' names from the file;
# W_structural when a material or link section damps (eta, damping, mass_damping not 0) and
# W_plastic when one yields (yield not 0) (a material no link uses would count too). A link
# with fidelity = pieces and N elements is links NAME, NAME_p1 .. NAME_pN, and its springs
# NAME_b1 .. NAME_bN follow the first joint whose body2 it is (else the file's joints).
header() {
  awk 'BEGIN { printf "t" }
       { line = $0; sub(/#.*/, "", line); n = split(line, w)
         if (n >= 2 && w[2] != "=" && w[1] ~ /^(solver|material|section|link|joint|load|actuator|coupling)$/) sec = w[1]
         if (sec == "material" || sec == "link")
           for (i = 1; i + 2 <= n; i++) if (w[i + 1] == "=" && w[i + 2] + 0 != 0) {
             if (w[i] == "eta" || w[i] == "damping" || w[i] == "mass_damping") structural = 1
             if (w[i] == "yield") plastic = 1 }
         for (i = 1; i + 2 <= n; i++) if (w[i + 1] == "=") {
           if (sec == "link" && w[i] == "fidelity" && w[i + 2] == "pieces") cut[nl] = 1
           if (sec == "link" && w[i] == "elements") el[nl] = w[i + 2]
           if (sec == "joint" && w[i] == "body2") b2[nj] = w[i + 2] } }
       $1 == "joint" && $2 != "=" { joints[++nj] = $2 }
       $1 == "link" && $2 != "=" { links[++nl] = $2; el[nl] = 10 }
       $1 == "actuator" && $2 != "=" { drives = 1 }
       END { for (k = 1; k <= nl; k++) { at[links[k]] = k; L[++nL] = links[k]; for (p = 1; cut[k] && p <= el[k]; p++) L[++nL] = links[k] "_p" p }
             for (j = 1; j <= nj; j++) { J[++nJ] = joints[j]; k = at[b2[j]]
               if (cut[k] && !done[k]) { done[k] = 1; for (p = 1; p <= el[k]; p++) J[++nJ] = links[k] "_b" p } }
             for (k = 1; k <= nl; k++) for (p = 1; cut[k] && !done[k] && p <= el[k]; p++) J[++nJ] = links[k] "_b" p
             n = split("theta_deg rate flag torque_spring torque_table torque_damping torque_friction torque_limit latch_impulse", c, " ");
             for (j = 1; j <= nJ; j++) {
               for (i = 1; i <= n; i++) printf ",%s.%s", J[j], c[i]
               if (drives) printf ",%s.torque_drive", J[j]
               printf ",%s.Fx,%s.Fy", J[j], J[j]
             }
             for (k = 1; k <= nL; k++) printf ",%s.tip_x,%s.tip_y,%s.tip_defl", L[k], L[k], L[k];
             print ",E_kin,E_strain,E_spring,E_gravity,W_applied" (drives ? ",W_drive" : "") ",W_damping,W_friction,W_limit" \
               (structural ? ",W_structural" : "") (plastic ? ",W_plastic" : "") ",E_balance" }' "$1"
}
# a joint's lock and first-contact times from an rj run summary on stderr: "LOCK FIRST"
summary_times() { # file, joint
  sed -n "s/^rj run: $2: first contact \([^ ]*\) s, lock \([^ ]*\) s.*/\2 \1/p" "$1"
}
# the time of the first row whose column NAME holds 3 (locked) in a CSV
first_locked_row() { # csv, column name
  awk -F, -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next } $k == 3 { print $1; exit }' "$1"
}

# ---- rj run on every scene: columns, rows
for f in $S/*.rjs; do
  n=$(basename $f .rjs)
  $B/rj run $f --t-end 0.05 --csv $T/$n.csv 2>$T/$n.err; st=$?
  if [ $st = 0 ] && [ "$(head -1 $T/$n.csv)" = "$(header $f)" ]; then echo "PASS rj: run $n: the header names every joint's, link's and energy column from the file"
  else echo "FAIL rj: run $n: status $st, header $(head -1 $T/$n.csv | cut -c1-200) want $(header $f | cut -c1-200)"; fi
  rows=$(($(wc -l < $T/$n.csv) - 1))
  if [ "$rows" = 51 ]; then echo "PASS rj: run $n --t-end 0.05: 51 rows (t-end / 1 ms + 1)"; else echo "FAIL rj: run $n --t-end 0.05: $rows rows, want 51"; fi
done
$B/rj run $S/impact.rjs --t-end 0.01 --sample 0 --csv $T/every.csv 2>/dev/null
ok "run --sample 0: a row every step (0.01 s / 2.5 us + 1 = 4001 rows)" "[ \$(wc -l < $T/every.csv) = 4002 ]"
$B/rj run $S/impact.rjs --t-end 0.02 --sample 0.005 --probe arm:last --probe base:3 --nodes $T/nodes.csv --csv $T/probe.csv 2>/dev/null
ok "run --probe arm:last --probe base:3: their x, y, phi columns before the energies" \
  "head -1 $T/probe.csv | grep -q ',arm.tip_defl,arm.10.x,arm.10.y,arm.10.phi,base.3.x,base.3.y,base.3.phi,E_kin,'"
ok "run --probe arm:last: the probe is the tip (the same x, y as arm.tip_x, arm.tip_y)" \
  "awk -F, 'NR > 1 && (\$16 != \$19 || \$17 != \$20) { exit 1 }' $T/probe.csv"
ok "run --nodes: a header and the 22 nodes, by link name" \
  "[ \$(wc -l < $T/nodes.csv) = 23 ] && head -1 $T/nodes.csv | grep -qx 'link,node,x,y,phi' && grep -q '^arm,10,' $T/nodes.csv"
m 2 "no link 'zzz'" "run --probe with an unknown link is refused" $B/rj run $S/impact.rjs --probe zzz:1 --csv /dev/null
m 2 "no link 'zzz'" "run --loads with an unknown link is refused" $B/rj run $S/impact.rjs --loads zzz --csv /dev/null
$B/rj run $S/deploy.rjs --t-end 0.01 --loads arm2 --csv $T/loads.csv 2>/dev/null
ok "run --loads arm2: N, V, M0, M1 of its 10 elements, numbers after the first step" \
  "head -1 $T/loads.csv | tr ',' '\\n' | grep -c '^arm2\\.[0-9]*\\.\\(N\\|V\\|M0\\|M1\\)\$' | grep -qx 40 &&
   awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if (\$i == \"arm2.0.M0\") k = i; next }
            NR > 2 && \$k !~ /^-?[0-9]/ { exit 1 }' $T/loads.csv"
m 2 "nodes 0..10" "run --probe with a node past the link's last is refused" $B/rj run $S/impact.rjs --probe arm:11 --csv /dev/null

# ---- rj run against build/deploy on the same scene: the joint angles row for row
$B/rj run $S/deploy.rjs --t-end 3.5 --csv $T/rj_deploy.csv 2>$T/rj_deploy.err
$B/deploy --scene $S/deploy.rjs --t-end 3.5 --csv $T/deploy.csv 2>$T/deploy.err
# rj: t, j1 (2-12, its pin force 11-12), j2 (13-23), arm1 (24-26), arm2 (27-29), energies
# (30-38); deploy from 39: t (%.6f: within half its last digit), q1 = j1 (deg), q2 = j2 -
# 180 (deg), rates, flags, tip2_x, tip2_y (%.10g)
res=$(paste -d, $T/rj_deploy.csv $T/deploy.csv | awk -F, '
  NR == 1 { next }
  { n++; d = $1 - $39; if (d < 0) d = -d; if (d > 5.001e-7) bad = bad " t@" $39
    if ($2 != $40) bad = bad " q1@" $39
    d = $13 - ($41 + 180); if (d < 0) d = -d; if (d > 2e-7) bad = bad " q2@" $39
    if ($3 != $42 || $14 != $43) bad = bad " rates@" $39
    if ($4 != $44 || $15 != $45) bad = bad " flags@" $39
    if ($27 != $46 || $28 != $47) bad = bad " tip2@" $39 }
  END { print n, substr(bad, 1, 200) }')
if [ "$res" = "3501 " ] && [ $(wc -l < $T/rj_deploy.csv) = $(wc -l < $T/deploy.csv) ]; then
  echo "PASS rj: run deploy.rjs = build/deploy --scene deploy.rjs row for row to 3.5 s (3501 rows: t, q1, q2 to the printed digits, rates, flags, tip 2 exact; joint 2 locks)"
else echo "FAIL rj: run deploy.rjs against build/deploy: rows, mismatches: $res"; fi

# ---- lock times: the library's event time, the flag change in the history, the same run twice
$B/rj run $S/deploy.rjs --t-end 4.2 --csv $T/lock.csv 2>$T/lock.err
$B/deploy --scene $S/deploy.rjs --t-end 4.2 --csv /dev/null 2>$T/lock_deploy.err
for j in 1 2; do
  set -- $(summary_times $T/lock.err j$j)
  lib=$(sed -n "s/.*joint $j locks at \([0-9.]*\) s.*/\1/p; s/.*joint $j at \([0-9.]*\) s.*/\1/p" $T/lock_deploy.err)
  mine=$(printf '%.6f' "$1")
  if [ -n "$1" ] && [ "$1" = "$2" ] && [ "$mine" = "$lib" ]; then
    echo "PASS rj: deploy.rjs j$j locks at $1 s: the summary's lock = its first contact (rj_joint_event_time) = build/deploy's $lib s"
  else echo "FAIL rj: deploy.rjs j$j: lock '$1', first contact '$2', build/deploy's rj_joint_event_time '$lib'"; fi
done
for n in solar_array solar_array_bus; do
  $B/rj run $S/$n.rjs --t-end 3.6 --sample 0.002 --csv $T/$n.lock.csv 2>$T/$n.lock.err
  $B/rj run $S/$n.rjs --t-end 3.6 --sample 0.002 --csv /dev/null 2>$T/$n.lock2.err
  for j in h1 h2 h3 h4; do
    set -- $(summary_times $T/$n.lock.err $j)
    row=$(first_locked_row $T/$n.lock.csv $j.flag)
    # the first locked row follows the lock's state within a sample (2 ms) and a step
    if [ -n "$1" ] && [ "$1" = "$2" ] && awk -v l="$1" -v r="$row" 'BEGIN { exit !(r > l && r <= l + 0.002 + 1e-4) }'; then
      echo "PASS rj: $n.rjs $j locks at $1 s (= rj_joint_event_time), its flag turns 3 in the history at $row s"
    else echo "FAIL rj: $n.rjs $j: lock '$1', first contact '$2', first locked row '$row'"; fi
  done
  ok "$n.rjs: two runs print the same events and lock times" \
    "grep -v wall $T/$n.lock.err > $T/a.txt; grep -v wall $T/$n.lock2.err > $T/b.txt; cmp -s $T/a.txt $T/b.txt && grep -c 'locked at' $T/a.txt | grep -qx 4"
done
$B/rj run $S/impact.rjs --t-end 0.02 --csv /dev/null 2>$T/impact.err
ok "impact.rjs: the contact's chatter (hundreds of flag changes) prints one first contact and one release" \
  "[ \$(grep -c 'hinge first contact with the reverse limit (176 deg)' $T/impact.err) = 1 ] && [ \$(grep -c 'released from' $T/impact.err) = 1 ] \
   && grep -Eq 'hinge: first contact 0.0069825 s, lock none, [0-9]{3} contacts' $T/impact.err"

# ---- exit statuses and messages
t 2 "run --bogus exits 2 with the usage" $B/rj run $S/deploy.rjs --bogus
t 2 "an unknown subcommand exits 2 with the usage" $B/rj frobnicate $S/deploy.rjs
t 2 "run without a scene exits 2 with the usage" $B/rj run --t-end 1
t 2 "run with two scenes exits 2 with the usage" $B/rj run $S/deploy.rjs $S/impact.rjs
t 2 "run --t-end with a malformed number exits 2 with the usage" $B/rj run $S/deploy.rjs --t-end 1x
t 2 "plot without --out exits 2 with the usage" $B/rj plot $S/deploy.rjs
t 2 "plot --what magic exits 2 with the usage" $B/rj plot $S/deploy.rjs --what magic --out $T/x.png
t 2 "check does not take run's --csv" $B/rj check $S/deploy.rjs --csv x.csv
ok "rj --help, rj run --help and rj help animate print the usage, status 0" \
  "$B/rj --help | grep -q 'usage: rj SUBCOMMAND' && $B/rj run --help | grep -q 'J.latch_impulse' && $B/rj help animate | grep -q -- '--mp4 FILE'"
m 2 "/dev/null/dir/x.csv" "run --csv /dev/null/dir/x.csv (a folder that cannot be made) exits 2 naming the path" \
  $B/rj run $S/deploy.rjs --csv /dev/null/dir/x.csv
ok "run --csv and --nodes into folders that do not exist yet make them" \
  "rm -rf $T/new && $B/rj run $S/deploy.rjs --t-end 0.01 --csv $T/new/a/h.csv --nodes $T/new/b/n.csv 2>/dev/null && test -s $T/new/a/h.csv && test -s $T/new/b/n.csv"
m 2 "/dev/null/n.csv" "run --nodes /dev/null/n.csv exits 2 naming the path" \
  $B/rj run $S/deploy.rjs --csv /dev/null --nodes /dev/null/n.csv
m 2 "/dev/null/p.png" "plot --out /dev/null/p.png exits 2 naming the path, before running" \
  $B/rj plot $S/deploy.rjs --out /dev/null/p.png
m 2 "nowhere.rjs: cannot open the file for reading" "run on a missing scene file exits 2 naming it" \
  $B/rj run $T/nowhere.rjs
m 2 "1e\+1[12] steps.*--force" "run --dt 1e-12 is refused (2) with the step count unless --force" \
  $B/rj run $S/deploy.rjs --dt 1e-12
m 2 "option --dt 0.001: solver.dt = 0.001 s is above the stability bound" "run --dt above the bound: the option is named" \
  $B/rj run $S/deploy.rjs --dt 1e-3
if [ -w /dev/full ]; then
  m 1 "/dev/full: No space left" "run --csv /dev/full exits 1 (a write that fails during the run)" $B/rj run $S/deploy.rjs --csv /dev/full
else echo "SKIP rj: no /dev/full here"; fi
# a closed pipe: quiet, status 0
{ $B/rj run $S/deploy.rjs --t-end 6 2>$T/pipe.err; echo $? > $T/pipe.st; } | head -3 > $T/pipe.out
ok "run deploy.rjs | head -3: status 0, three lines read, nothing on standard error" \
  "[ \$(cat $T/pipe.st) = 0 ] && [ \$(wc -l < $T/pipe.out) = 3 ] && [ ! -s $T/pipe.err ]"
# the progress line goes to standard error only
$B/rj run $S/impact.rjs --t-end 0.01 --progress > $T/prog.csv 2>$T/prog.err
$B/rj run $S/impact.rjs --t-end 0.01 > $T/noprog.csv 2>/dev/null
ok "run --progress: a progress line on standard error, the same CSV as without it" \
  "grep -q '100.0 %  t = 0.01 s' $T/prog.err && cmp -s $T/prog.csv $T/noprog.csv"

# ---- a simulation that stops: status 1, the library's message, the history up to the last good state
sed 's/^  dt = 7.5e-6 .*/  dt = 3e-5\n  allow_unstable = yes/' $S/deploy.rjs > $T/blowup.rjs
$B/rj run $T/blowup.rjs --sample 0.01 --csv $T/blowup.csv 2>$T/blowup.err; st=$?
tl=$(sed -n 's/.*simulation stopped after t = \([^ ]*\) s.*/\1/p' $T/blowup.err)
ok "run with dt above the bound (allow_unstable): status 1, the blow-up message, the CSV ends at the last good state (t = $tl s)" \
  "[ $st = 1 ] && grep -q 'numerical blow-up' $T/blowup.err && [ -n '$tl' ] && [ \"\$(tail -1 $T/blowup.csv | cut -d, -f1)\" = '$tl' ]"

# ---- rj check
ok "check deploy.rjs: valid, status 0" "$B/rj check $S/deploy.rjs | grep -qx '$S/deploy.rjs: valid'"
for f in $S/*.rjs; do
  ok "check $(basename $f): links, joints, the bound and what sets it, the cost of a second and of the build" \
    "$B/rj check $f > $T/check.txt && grep -q '^links: ' $T/check.txt && grep -q '^joints: ' $T/check.txt \
     && grep -q 'stability bound' $T/check.txt && grep -q 'the bound is set by ' $T/check.txt && grep -q '^cost: 1 simulated second' $T/check.txt \
     && grep -Eq '^cost: building the model took [0-9.e+-]+ ms, as long as [0-9]+ steps' $T/check.txt"
done
ok "check elastica.rjs: its load, node, force and table; flexible_pendulum.rjs: its gravity" \
  "$B/rj check $S/elastica.rjs | grep -qx '  tip          beam last node: force (0, -74.6667) N fixed, moment 0 N m; a table of 2 points from 0 to 0.5 s' \
   && $B/rj check $S/flexible_pendulum.rjs | grep -qx 'gravity: (0, -9.81) m/s^2' && ! $B/rj check $S/deploy.rjs | grep -q '^loads:\\|^gravity:'"
ok "check impact.rjs: the adaptive hinge sets the bound, deploy.rjs: link arm2 does" \
  "$B/rj check $S/impact.rjs | grep -q 'set by joint hinge' && $B/rj check $S/deploy.rjs | grep -q 'set by link arm2'"
printf 'link a\n  length 1\n' > $T/syntax.rjs
printf 'link a\n  lenght = 1\n' > $T/unknown.rjs
printf 'link a\n  length = -1\n' > $T/range.rjs
printf 'link a\njoint j\n  body1 = ground  body2 = a  forward = 10 deg  method = penalty\n' > $T/model.rjs
m 2 "^$T/syntax.rjs:2:[0-9]+: " "check on a syntax error: 2, file:line:col" $B/rj check $T/syntax.rjs
m 2 "^$T/unknown.rjs:2:3: unknown key 'lenght' in link 'a'; did you mean 'length'\?" "check on an unknown key: 2, the parser's message" $B/rj check $T/unknown.rjs
m 2 "^$T/range.rjs:2:12: length = -1 is out of range" "check on an invalid value: 2, file:line:col" $B/rj check $T/range.rjs
m 2 "^$T/model.rjs:3:[0-9]+: joints\[0\].penalty_k = 0 is invalid.*joint 'j'" "check on a scene the model rejects: 2, located by rj_scene_file_locate" $B/rj check $T/model.rjs
# ---- rj check --assemble: the four-bar written a few degrees off
sed -e 's/^  angle0 = -3.618177287764351 .*/  angle0 = -205 deg/' -e 's/^  angle0 = 1.581333937590354 .*/  angle0 = 88 deg/' \
    -e 's/^  angle0 = -2.1308716330214788 .*/  angle0 = -125 deg/' $S/fourbar.rjs > $T/fourbar_off.rjs
m 2 "joints\[3\] closes a loop, but the other joints place its pins" "check on a four-bar whose loop does not close: 2, the gap named" $B/rj check $T/fourbar_off.rjs
ok "check --assemble: the loop closed, written, and that scene valid with the crank at 60 deg" \
  "$B/rj check $T/fourbar_off.rjs --assemble $T/fourbar_closed.rjs > $T/asm.txt 2>$T/asm.err \
   && grep -qx '$T/fourbar_closed.rjs: valid' $T/asm.txt && grep -q 'closes a loop' $T/asm.txt \
   && grep -q '(3 angle0 moved)' $T/asm.err && grep -q '^  angle0 = 60 deg' $T/fourbar_closed.rjs"
sed -e 's/^  length = 1.0  elements = 10/  length = 0.05  elements = 10/' $S/fourbar.rjs > $T/fourbar_short.rjs
m 2 "joints\[3\] closes cannot close: its pins stay 0.0388194 m apart at best" "check --assemble on a loop that cannot close: 2, its least gap named" \
  $B/rj check $T/fourbar_short.rjs --assemble $T/never.rjs
printf 'solver\n  dt = 0\nlink a\n  length = 1  elements = 4  tip_mass = 200\njoint j1\n  body1 = ground  body2 = a\n  angle0 = 100 deg  forward = 90 deg\n' > $T/warn.rjs
sed 's/penalty_k = 1014.8544308316433/penalty_k = 5000/' $S/deploy.rjs > $T/eq31.rjs
# (this scene's adaptive limit, caught 10 deg late, may blow up its first steps: rj check
# then says it is not valid and exits 1, and still prints the warnings, which are checked here)
ok "check warns: a limit the joint starts past (the model's, named), a heavy tip mass on 4 elements, K above Eq 31" \
  "$B/rj check $T/warn.rjs > $T/w.txt 2>/dev/null; grep -q \"starts 10 deg past its forward limit (joint 'j1')\" $T/w.txt \
   && grep -q 'link a: tip mass 200 kg is 7.38 x' $T/w.txt && $B/rj check $T/eq31.rjs | grep -q 'joint j2: penalty_k 5000 N m/rad is above Eq 31'"
ok "check warns of nothing on deploy.rjs" "$B/rj check $S/deploy.rjs | grep -qx 'warnings: none'"

# ---- rj plot
for w in angles torques tips energy loads; do
  ok "plot --what $w writes a PNG" \
    "$B/rj plot $S/solar_array.rjs --t-end 0.2 --what $w --size 320x200 --out $T/plot_$w.png 2>/dev/null && [ \"\$(head -c 4 $T/plot_$w.png | od -An -tx1 | tr -d ' \\n')\" = 89504e47 ]"
done
ok "plot: the 4 joints of solar_array fit; no series dropped" "! $B/rj plot $S/solar_array.rjs --t-end 0.01 --out $T/p.png 2>&1 | grep -q 'plotting the first'"

# ---- rj animate: the frames of build/animate, byte for byte (the caption is the file name:
# run where the scene file is, so that build/animate's caption, the path, is the same)
(cd $S && $AB/rj animate deploy.rjs --t-end 0.4 --fps 10 --size 200x150 --out $AT/rja --plain 2>/dev/null) \
  && (cd $S && $AB/animate --scene deploy.rjs --t-end 0.4 --fps 10 --size 200x150 --out $AT/anim 2>/dev/null)
same=1
for f in $T/anim/frame_*.png; do cmp -s $f $T/rja/$(basename $f) || same=0; done
ok "animate deploy.rjs = build/animate --scene deploy.rjs: 5 frames, byte-equal PNGs" \
  "[ $same = 1 ] && [ \$(ls $T/rja | wc -l) = 5 ] && [ \$(ls $T/anim | wc -l) = 5 ]"
m 0 "ffmpeg -y -loglevel error -framerate 10 -i $T/mp4/frame_%05d.png -pix_fmt yuv420p $T/x.mp4" \
  "animate --mp4 without ffmpeg on PATH prints the command to run" \
  env PATH=/nonexistent $B/rj animate $S/deploy.rjs --t-end 0.1 --fps 10 --size 64x48 --out $T/mp4 --mp4 $T/x.mp4
mkdir -p $T/blocked/frame_00000.png
m 1 "$T/blocked/frame_00000.png.*Is a directory" "animate fails (1) naming the frame it cannot write" \
  $B/rj animate $S/deploy.rjs --t-end 0.1 --out $T/blocked

# ---- gravity and --settle: a cantilever under its own weight starts from its sag, at rest;
# the sag against beam theory with the lumped loads of 10 elements (5.694705e-3 m, within
# 3e-5: the co-rotational beam's shortening), and it stays there
printf 'solver\n  gravity = 0 -9.81\nlink beam\n  length = 1  elements = 10\n  E = 7e10  rho = 2700\n  width = 0.02  height = 0.01\n  root = clamped\n' > $T/cantilever.rjs
# a clamped cantilever under a 2 N tip load, settled: the peak bending moment is the
# clamp's, P times the deflected arm (1.99996 N m: rj_element_loads' statics check)
printf 'solver\n  gravity = 0 0\nlink beam\n  length = 1  elements = 10\n  E = 7e10  rho = 2700\n  width = 0.02  height = 0.01\n  root = clamped\nload tip\n  link = beam  node = last  force = 0 -2\n' > $T/tipload.rjs
$B/rj run $T/tipload.rjs --settle --t-end 0.05 --loads beam --csv /dev/null 2>$T/tipload.err
ok "run --loads: the summary's peak bending moment, a settled cantilever: P L at the clamp" \
  "grep -q 'beam: peak |bending moment| 1.9999[0-9]* N m at element 0, its first node' $T/tipload.err"
# a rigid rod of 0.54 kg released level: its pin carries 2.5 m g = 13.2435 N at the bottom,
# the largest force of its swing (rj run's summary, from rj_joint_pin_forces)
printf 'solver\n  dt = 1e-4  gravity = 0 -9.81\nlink rod\n  length = 1  rho = 2700  width = 0.02  height = 0.01\n  fidelity = rigid\njoint pin\n  body1 = ground  body2 = rod  angle0 = 0\n' > $T/rod.rjs
$B/rj run $T/rod.rjs --t-end 1 --csv /dev/null 2>$T/rod.err
ok "run: the summary's peak pin force, a rod released level: 2.5 m g at the bottom" \
  "sed -n 's/.*peak |pin force| \\([0-9.e+-]*\\) N.*/\\1/p' $T/rod.err | awk '{ v = \$1 } END { exit !(NR == 1 && v > 13.2435 * (1 - 1e-3) && v < 13.2435 * (1 + 1e-3)) }'"
# a link of 500 elements steps in place by default (solver.in_place, automatic from 400
# nodes), which keeps no element loads at t^n: rj run steps it double-buffered (the same bits), so
# its pin's J.Fx has a number in every row after the first (none before a step) and the
# summary a peak
printf 'solver\n  gravity = 0 -9.81\nlink long\n  length = 1  elements = 500\n  E = 7e10  rho = 2700  width = 0.02  height = 0.01\njoint pin\n  body1 = ground  body2 = long  angle0 = 0\n' > $T/long.rjs
$B/rj run $T/long.rjs --t-end 1e-4 --sample 2e-5 --csv $T/long.csv 2>$T/long.err
ok "run: a link of 500 elements (in place by default) has pin forces: pin.Fx a number in every row after the first, the summary's peak" \
  "awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if (\$i == \"pin.Fx\") k = i; next }
     NR > 2 { n++; if (\$k != \"\" && \$k + 0 == \$k) f++ } END { exit !(k && n >= 4 && f == n) }' $T/long.csv \
   && grep -q '^rj run: pin: .*peak |pin force| [0-9][0-9.e+-]* N' $T/long.err"
$B/rj run $T/cantilever.rjs --settle --t-end 0.05 --sample 0.01 --csv $T/sag.csv 2>$T/sag.err
ok "run --settle: the cantilever starts from its sag under gravity and stays there" \
  "grep -q 'settled to the static equilibrium' $T/sag.err && awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if (\$i == \"beam.tip_y\") y = i; if (\$i == \"E_gravity\") g = i } next }
     { d = -\$y / 5.694705e-3 - 1; if (d < 0) d = -d; if (d > 3e-5 || \$g >= 0) exit 1; n++ } END { exit n < 5 }' $T/sag.csv"
ok "run without --settle: the same cantilever starts straight" \
  "$B/rj run $T/cantilever.rjs --t-end 0 --csv - 2>/dev/null | awk -F, 'NR == 2 { exit !(\$3 == 0) }'"

# ---- a load section: the elastica scene settles to the classical large-deflection shape
# (tip v/L 0.8106090, u/L 0.5549956 at P L^2 / EI = 10: tests/elastica_ref.py) within the
# mesh error of 40 elements (second order: 8e-5 measured), and its load did the work
$B/rj run $S/elastica.rjs --settle --t-end 0 --csv $T/elastica.csv 2>$T/elastica.err
ok "run --settle: the elastica scene's tip against the large-deflection solution" \
  "grep -q 'settled to the static equilibrium' $T/elastica.err && awk -F, 'NR == 2 { v = -\$3 - 0.8106090; u = 1 - \$2 - 0.5549956;
     if (v < 0) v = -v; if (u < 0) u = -u; exit !(v < 2e-4 && u < 2e-4) }' $T/elastica.csv"
ok "run: the elastica scene's ramped load does work, and the balance closes" \
  "$B/rj run $S/elastica.rjs --t-end 0.6 --sample 0.1 --csv - 2>/dev/null | awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if (\$i == \"W_applied\") w = i; if (\$i == \"E_balance\") b = i } next }
     { last_w = \$w; bal = \$b < 0 ? -\$b : \$b; if (bal > 1e-6 * (last_w + 1e-3)) exit 1 } END { exit !(last_w > 1) }'"

# ---- a PNG that cannot be written: a clear message, and nothing the program did not
# create is removed. As root, a private copy of /dev/full first (so that a regression
# removes the copy, not /dev/full); /dev/full itself only once the copy survived.
dev_ok=0
if mknod $T/full c 1 7 2>/dev/null; then
  m 1 "cannot write $T/full: error writing $T/full: No space left on device" "plot --out onto a full device (a copy of /dev/full) fails (1) saying why" \
    $B/rj plot $S/deploy.rjs --t-end 0.01 --out $T/full
  if [ -c $T/full ]; then dev_ok=1; echo "PASS rj: plot --out a device that cannot be written: the device is still there"
  else echo "FAIL rj: plot --out a device that cannot be written removed it"; fi
elif [ "$(id -u)" != 0 ]; then dev_ok=1; fi
if [ $dev_ok = 1 ] && [ -w /dev/full ]; then
  m 1 "cannot write /dev/full: .*No space left on device" "plot --out /dev/full fails (1) saying why" $B/rj plot $S/deploy.rjs --t-end 0.01 --out /dev/full
  ok "plot --out /dev/full: /dev/full is still a character device" "[ -c /dev/full ]"
else echo "SKIP rj: plot --out /dev/full (no /dev/full, or its copy did not survive)"; fi
# a file size limit (ulimit -f, SIGXFSZ ignored) makes writing a regular file fail: a file
# that was there is left (cut short), one the plot created is removed
echo keep > $T/kept.png
m 1 "cannot write $T/kept.png: error writing $T/kept.png: File too large" "plot --out a file whose write fails (file size limit) fails (1) saying why" \
  sh -c "trap '' XFSZ; ulimit -f 1; exec $B/rj plot $S/deploy.rjs --t-end 0.01 --out $T/kept.png"
ok "plot: a file that was there before a failed write is not removed" "[ -f $T/kept.png ]"
sh -c "trap '' XFSZ; ulimit -f 1; exec $B/rj plot $S/deploy.rjs --t-end 0.01 --out $T/made.png" 2>/dev/null
ok "plot: a file the failed write created is removed, not left half written" "[ ! -e $T/made.png ]"

# ---- plot labels that do not hide each other: four locks, j1's and j4's 11 ms apart
# (both in the first row of labels as they were), against the same locks far apart. The
# labels' text pixels (their colour exactly, 0x5a34a8) count the same when none covers
# another.
locks() { # file, j4's forward limit (deg): rigid links turning at 1 rad/s lock at it
  : > $1
  for j in 1 2 3 4; do
    case $j in 1) f=17.1887;; 2) f=34.3775;; 3) f=51.5662;; 4) f=$2;; esac
    printf 'link a%d\n  fidelity = rigid  length = 1\njoint j%d\n  body1 = ground  body2 = a%d  ground_y = %d\n  angle0 = 0 deg  rate0 = 1  forward = %s deg  lock = yes\n' $j $j $j $j $f >> $1
  done
}
locks $T/locks_close.rjs 17.7617
locks $T/locks_far.rjs 5.7296
# the number of pixels of one colour in each PNG rjr_write_png wrote (8-bit RGB, filter none)
if [ -x /usr/bin/python3 ]; then
  $B/rj plot $T/locks_close.rjs --out $T/locks_close.png 2>/dev/null
  $B/rj plot $T/locks_far.rjs --out $T/locks_far.png 2>/dev/null
  close=$(/usr/bin/python3 tools/png_count.py $T/locks_close.png 5a34a8 | cut -d' ' -f2)
  far=$(/usr/bin/python3 tools/png_count.py $T/locks_far.png 5a34a8 | cut -d' ' -f2)
  ok "plot --what angles: lock labels 11 ms apart do not hide each other (label pixels $close close, $far far apart)" "[ -n '$close' ] && [ '$close' -gt 0 ] && [ '$close' = '$far' ]"
else echo "SKIP rj: no /usr/bin/python3 to count the plot's label pixels"; fi

# ---- rj plot --what loads: pin forces above, the flexible links' largest bending moments
# below; a joint the library has no pin force for is said, not drawn
# a file's first 4 bytes in hex (a PNG's: 89504e47), expanded before ok runs its check
magic() { head -c 4 "$1" | od -An -tx1 | tr -d ' \n'; }
$B/rj plot $S/deploy.rjs --t-end 3.2 --what loads --size 640x480 --out $T/loads_deploy.png 2>$T/loads_deploy.err; st=$?
ok "plot deploy.rjs --what loads: a PNG (status $st), both joints with a pin force (no note), both arms' peak moments kept" \
  "[ $st = 0 ] && [ '$(magic $T/loads_deploy.png)' = 89504e47 ] && ! grep -q 'none in the whole run' $T/loads_deploy.err \
   && grep -q '^rj plot: arm1: peak |bending moment| ' $T/loads_deploy.err && grep -q '^rj plot: arm2: peak |bending moment| ' $T/loads_deploy.err"
# solar_array_bus.rjs: a rigid bus (no element loads: no moment series) and four flexible panels
$B/rj plot $S/solar_array_bus.rjs --t-end 0.2 --what loads --out $T/loads_bus.png 2>$T/loads_bus.err; st=$?
ok "plot solar_array_bus.rjs --what loads (a rigid bus): a PNG (status $st), moments of the 4 flexible panels only" \
  "[ $st = 0 ] && [ '$(magic $T/loads_bus.png)' = 89504e47 ] && [ \$(grep -c ': peak |bending moment| ' $T/loads_bus.err) = 4 ] \
   && ! grep -q '^rj plot: bus: peak |bending' $T/loads_bus.err"
# a loop-closing joint with the paper's chord reference: the library has no pin force for
# it (j3: a triangle of two flexible bars from ground pivots), it has one for the others
printf 'solver\n  gravity = 0 -9.81\nlink a\n  length = 0.5  elements = 4\nlink b\n  length = 0.5  elements = 4\njoint j1\n  body1 = ground  body2 = a  angle0 = 45 deg\njoint j2\n  body1 = ground  body2 = b  node2 = last  ground_x = 0.70710678118654757  angle0 = 315 deg\njoint j3\n  body1 = a  body2 = b  angle0 = 90 deg  reference = chord\n' > $T/mixed_loads.rjs
$B/rj plot $T/mixed_loads.rjs --t-end 0.05 --what loads --out $T/loads_mixed.png 2>$T/loads_mixed.err; st=$?
ok "plot --what loads, a joint without a pin force: said on standard error by name and not drawn, the others drawn (status $st)" \
  "[ $st = 0 ] && [ '$(magic $T/loads_mixed.png)' = 89504e47 ] \
   && grep -qx 'rj plot: j3 pin force: none in the whole run (rj_joint_pin_force has none for this joint): not plotted' $T/loads_mixed.err \
   && [ \$(grep -c 'none in the whole run' $T/loads_mixed.err) = 1 ]"
# a plot holds 8 series: the scissor boom's 16 joints and 12 flexible links, 8 of each
m 0 "16 pin force series, more than a plot holds: plotting the first 8" "plot scissor_boom.rjs --what loads: 8 of its 16 pin forces" \
  $B/rj plot $S/scissor_boom.rjs --t-end 0.01 --what loads --out $T/loads_scissor.png
m 0 "12 bending moment series, more than a plot holds: plotting the first 8" "plot scissor_boom.rjs --what loads: 8 of its 12 links' moments" \
  $B/rj plot $S/scissor_boom.rjs --t-end 0.01 --what loads --out $T/loads_scissor.png
# a rigid rod released level (all links rigid, no limits: no events): its pin force's peak
# (2.5 m g at the bottom) is marked, so the plot has marker-label pixels that its angles'
# plot, without events, has not
printf 'solver\n  dt = 1e-4  gravity = 0 -9.81\nlink rod\n  length = 1  rho = 2700  width = 0.02  height = 0.01\n  fidelity = rigid\njoint pin\n  body1 = ground  body2 = rod  angle0 = 0\n' > $T/rod_loads.rjs
$B/rj plot $T/rod_loads.rjs --what loads --out $T/loads_rod.png 2>$T/loads_rod.err; st=$?
$B/rj plot $T/rod_loads.rjs --what angles --out $T/angles_rod.png 2>/dev/null
ok "plot --what loads on a rigid rod: a PNG (status $st), no note, no moment plot (no flexible link)" \
  "[ $st = 0 ] && [ '$(magic $T/loads_rod.png)' = 89504e47 ] && ! grep -q 'none in the whole run\|bending' $T/loads_rod.err"
if [ -x /usr/bin/python3 ]; then
  loads=$(/usr/bin/python3 tools/png_count.py $T/loads_rod.png 5a34a8 | cut -d' ' -f2)
  angles=$(/usr/bin/python3 tools/png_count.py $T/angles_rod.png 5a34a8 | cut -d' ' -f2)
  ok "plot --what loads: the pin force's peak is marked (label pixels $loads, without events; $angles in the angles' plot)" "[ -n '$loads' ] && [ '$loads' -gt 0 ] && [ '$angles' = 0 ]"
else echo "SKIP rj: no /usr/bin/python3 to count the plot's label pixels"; fi

# ---- numbers are decimal, finite where they must be, the option and value named
m 2 "option --t-end: bad value '0x10' \(need a finite decimal number" "run --t-end 0x10 (hex) is refused" $B/rj run $S/deploy.rjs --t-end 0x10 --csv /dev/null
m 2 "option --sample: bad value 'nan' \(need a finite decimal number" "run --sample nan is refused" $B/rj run $S/deploy.rjs --sample nan --csv /dev/null
m 2 "option --fps: bad value 'inf' \(need a finite decimal number" "animate --fps inf is refused" $B/rj animate $S/deploy.rjs --fps inf --out $T/inf
m 2 "option --dt: bad value '1e' " "check --dt 1e (an exponent without digits) is refused" $B/rj check $S/deploy.rjs --dt 1e

# ---- "did you mean": options, subcommands and values
m 2 "^rj run: unknown option '--tend'; did you mean '--t-end'\?" "run --tend: did you mean '--t-end'" $B/rj run $S/deploy.rjs --tend 1
m 2 "^rj run: unknown option '--setle'; did you mean '--settle'\?" "run --setle: did you mean '--settle'" $B/rj run $S/deploy.rjs --setle
m 2 "^rj: unknown subcommand 'runn'; did you mean 'run'\?" "rj runn: did you mean 'run'" $B/rj runn $S/deploy.rjs
m 2 "^rj: unknown subcommand 'chek'; did you mean 'check'\?" "rj chek: did you mean 'check'" $B/rj chek $S/deploy.rjs
m 2 "^rj check: unknown option '--csv' \(rj run takes it, not rj check\)" "check --csv: named as rj run's option" $B/rj check $S/deploy.rjs --csv x.csv
m 2 "option --what: unknown value 'angle' \(one of: angles, torques, tips, energy, loads\); did you mean 'angles'\?" \
  "plot --what angle: the values listed, did you mean 'angles'" $B/rj plot $S/deploy.rjs --what angle --out $T/x.png
m 2 "^rj run: unknown option '--zzz'$" "run --zzz: nothing near, no suggestion" $B/rj run $S/deploy.rjs --zzz

# ---- rj check on a scene whose first steps fail (dt above the bound, allow_unstable: a
# blow-up within 20 steps): not valid, status 1, the library's reason on standard error
$B/rj check $T/blowup.rjs > $T/check_blowup.txt 2>$T/check_blowup.err; st=$?
ok "check on a scene whose first steps blow up: status 1 ($st), 'not valid', the cost line and standard error say why" \
  "[ $st = 1 ] && head -1 $T/check_blowup.txt | grep -q ': not valid: it cannot be simulated: a step fails at t = ' \
   && ! grep -q ': valid\$' $T/check_blowup.txt && grep -q '^cost: the first steps fail at t = ' $T/check_blowup.txt \
   && grep -q 'cannot be simulated: t = .*exceeds' $T/check_blowup.err"
# progress: every phase with --progress; without it once the check has taken 1 s (a
# 400000-element link: about 1.9 s and 290 MB here, building it twice)
ok "check --progress: the phases on standard error, with the wall time, and the end" \
  "$B/rj check $S/deploy.rjs --progress 2>&1 >/dev/null | grep -Eq '^rj check: [0-9.]+ s: timing 200-step batches \(22 nodes\)' \
   && $B/rj check $S/deploy.rjs --progress 2>&1 >/dev/null | grep -Eq '^rj check: [0-9.]+ s: done'"
printf 'link beam\n  length = 1  elements = 400000\n  root = clamped\n' > $T/long_check.rjs
$B/rj check $T/long_check.rjs > $T/long_check.txt 2>$T/long_check.err; st=$?
ok "check of a 400000-element link (over 1 s) without --progress: its phases on standard error, status 0 ($st)" \
  "[ $st = 0 ] && grep -Eq '^rj check: [0-9.]+ s: (building|timing)' $T/long_check.err && grep -Eq '^rj check: [0-9.]+ s: done' $T/long_check.err \
   && head -1 $T/long_check.txt | grep -q ': valid\$'"

# ---- --settle keeps the library's time: the elastica's load ramps on over 0.5 s, so it
# settles past 0.5 s; the run starts there (its first row), lasts --t-end from there, and
# the message says at what time it settled
$B/rj run $S/elastica.rjs --settle --t-end 0.01 --sample 0.005 --csv $T/settle_t.csv 2>$T/settle_t.err
ts=$(sed -n 's/.*settled to the static equilibrium at t = \([^ ]*\) s.*/\1/p' $T/settle_t.err)
ok "run --settle: the run starts at the settled time ($ts s, past the load's ramp) and lasts --t-end 0.01 s from it: 3 rows at 5 ms" \
  "[ -n '$ts' ] && awk -F, -v ts='$ts' 'NR == 1 { next } { t[++n] = \$1 }
     END { d = t[1] - ts; if (d < 0) d = -d; e = t[n] - t[1] - 0.01; if (e < 0) e = -e; exit !(n == 3 && ts > 0.5 && d < 1e-8 && e < 5e-6) }' $T/settle_t.csv"
# settling shows progress: a 300-element cantilever settles in about a second
sed 's/elements = 10/elements = 300/' $T/cantilever.rjs > $T/cantilever300.rjs
$B/rj run $T/cantilever300.rjs --settle --t-end 0 --progress --csv /dev/null 2>$T/settle_p.err
ok "run --settle --progress: progress lines while it settles (steps, time), then the settled time" \
  "grep -Eq '^rj run: settling: [0-9]+ steps \(at most 1e\+07\), t = ' $T/settle_p.err && grep -q 'settled to the static equilibrium at t = ' $T/settle_p.err"
# the bound on a run's length counts the settling's 1e7 steps: 700 s of deploy.rjs are
# 9.3e7 steps, under 1e8 alone, over it with --settle
m 2 "9.33e\+07 steps.*up to 1e\+07 settling steps.*--force" "run --settle --t-end 700: the run's and the settling's steps together are refused (2)" \
  timeout 60 $B/rj run $S/deploy.rjs --settle --t-end 700 --csv /dev/null

# ---- links that pass through each other: a rigid link turning at 10 rad/s about the tip
# of a fixed one, from straight (180 deg), lies over it at 360 deg (t = 0.314 s; reported
# once it is 1 deg past, 0.316 s) and again at 720 deg: one event line, not repeated as
# a warning, and the summary's time
printf 'link a\n  fidelity = rigid  length = 1  root = fixed\nlink b\n  fidelity = rigid  length = 1\njoint j2\n  body1 = a  body2 = b  angle0 = 180 deg  rate0 = 10\n' > $T/overlap.rjs
$B/rj run $T/overlap.rjs --t-end 1 --csv /dev/null 2>$T/overlap.err
ok "run: a joint whose links pass through each other: one event (t = 0.316 s, 360 deg), no warning repeating it, the summary's time" \
  "[ \$(grep -c 'passed through each other' $T/overlap.err) = 1 ] \
   && grep -qx 'rj run: t = 0.316 s: j2: links a and b passed through each other (it turned through 360 deg; links do not contact each other)' $T/overlap.err \
   && grep -q '^rj run: j2: first contact none, .*, links overlap 0.316 s\$' $T/overlap.err"
# ---- solar_array_yield.rjs: the array on an aluminium root strip p1 that yields (1100-O,
# 35 MPa, 16 layers), every link with mass_damping, against its elastic twin (yield = 0,
# by sed). To 5 s: every hinge has latched (h1 last, at 4.02 s; 3.85 s elastic) and p1 has
# yielded, from 3.12 s. About 1.5 s for the two runs.
Y=$S/solar_array_yield.rjs
sed 's/yield = 35e6/yield = 0/' $Y > $T/yield_elastic.rjs
$B/rj run $Y --t-end 5 --sample 0.01 --loads p1 --csv $T/yield.csv 2>$T/yield.err; st=$?
$B/rj run $T/yield_elastic.rjs --t-end 5 --sample 0.01 --loads p1 --csv $T/yield_el.csv 2>$T/yield_el.err; st_el=$?
ok "solar_array_yield.rjs and its elastic twin run to 5 s (status $st, $st_el), every hinge locks in both" \
  "[ $st = 0 ] && [ $st_el = 0 ] && grep -q '^  yield = 0 ' $T/yield_elastic.rjs && ! grep -q 'yield = 35e6' $T/yield_elastic.rjs \
   && grep -q '^rj run: done at t = 5' $T/yield.err && [ \$(grep -c 'locked at' $T/yield.err) = 4 ] && [ \$(grep -c 'locked at' $T/yield_el.err) = 4 ]"
# the last row's value of column NAME in a CSV, empty when there is no such column
last_of() { # csv, column name
  awk -F, -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next } END { if (k) print $k }' "$1"
}
wp=$(last_of $T/yield.csv W_plastic); ws=$(last_of $T/yield.csv W_structural); bal=$(last_of $T/yield.csv E_balance)
ws_el=$(last_of $T/yield_el.csv W_structural); bal_el=$(last_of $T/yield_el.csv E_balance)
ok "solar_array_yield.rjs: W_plastic $wp J at 5 s, its elastic twin has no W_plastic column; both book W_structural ($ws, $ws_el J)" \
  "awk 'BEGIN { exit !(\"$wp\" + 0 > 1 && \"$ws\" + 0 > 0 && \"$ws_el\" + 0 > 0) }' && ! head -1 $T/yield_el.csv | tr , '\\n' | grep -qx W_plastic"
ok "solar_array_yield.rjs: the energy balance closes with W_plastic in it, to 1 % of it ($bal J of $wp J; elastic twin $bal_el J)" \
  "awk 'BEGIN { b = \"$bal\" + 0; e = \"$bal_el\" + 0; exit !(b < 0.01 * \"$wp\" && -b < 0.01 * \"$wp\" && e < 1e-4 && -e < 1e-4) }'"
# layers that have not yielded are the elastic element to the bit: the two histories, less
# the W_plastic column, are the same up to the row before p1 first yields, and differ there
k=$(head -1 $T/yield.csv | tr , '\n' | grep -nx W_plastic | cut -d: -f1)
first=$(awk -F, -v k="$k" 'NR > 1 && $k > 0 { print NR; exit }' $T/yield.csv)
ty=$(sed -n "${first:-1}p" $T/yield.csv | cut -d, -f1)
cut -d, -f1-$((k - 1)),$((k + 1))- $T/yield.csv > $T/yield_less.csv
ok "solar_array_yield.rjs: the history is its elastic twin's to the bit until p1 first yields (t = $ty s, after h4 and h3 latch), then not" \
  "[ -n '$first' ] && awk 'BEGIN { exit !(\"$ty\" + 0 > 1.7) }' && head -n $((${first:-2} - 1)) $T/yield_less.csv > $T/a.txt && head -n $((${first:-2} - 1)) $T/yield_el.csv > $T/b.txt \
   && cmp -s $T/a.txt $T/b.txt && [ \"\$(sed -n '${first:-1}p' $T/yield_less.csv)\" != \"\$(sed -n '${first:-1}p' $T/yield_el.csv)\" ]"
# the peaks from the summaries: p1's bending moment and stress, h1's pin force
peak_m() { sed -n 's/^rj run: p1: peak |bending moment| \([0-9.e+]*\) N m.*/\1/p' "$1"; }
peak_s() { sed -n 's/^rj run: p1: .*peak outer-fibre stress \([0-9.e+]*\) Pa$/\1/p' "$1"; }
peak_f() { sed -n 's/^rj run: h1: .*peak |pin force| \([0-9.e+]*\) N,.*/\1/p' "$1"; }
my=$(peak_m $T/yield.err); me=$(peak_m $T/yield_el.err); sy=$(peak_s $T/yield.err); se=$(peak_s $T/yield_el.err)
# p1's collapse moment: 35e6 x 0.06 x 0.015^2 / 4 = 118.1 N m (the hardening adds a little)
ok "solar_array_yield.rjs: p1's root carries less when it yields: peak moment $my N m against $me elastic (collapse 118.1), stress $sy against $se Pa" \
  "awk 'BEGIN { my = \"$my\" + 0; me = \"$me\" + 0; sy = \"$sy\" + 0; se = \"$se\" + 0
                exit !(my > 100 && my < 1.1 * 118.1 && me > 1.5 * 118.1 && sy > 0.999 * 35e6 && sy < 40e6 && se > 2 * 35e6) }'"
fy=$(peak_f $T/yield.err); fe=$(peak_f $T/yield_el.err)
ok "solar_array_yield.rjs: h1's peak pin force is lower when p1 yields ($fy N against $fe N elastic)" \
  "awk 'BEGIN { exit !(\"$fy\" + 0 > 0 && \"$fy\" + 0 < 0.8 * \"$fe\") }'"
# ---- the renderer is loaded only to draw: rj check and rj run never open OSMesa (nor LLVM),
# rj plot does (dlopen on its first rjr_create); the dynamic loader's own log says which
# libraries a process opened (LD_DEBUG=libs, on standard error)
LD_DEBUG=libs $B/rj check $S/deploy.rjs > /dev/null 2> $T/ld_check.txt; st=$?
LD_DEBUG=libs $B/rj run $S/deploy.rjs --t-end 0.001 --csv /dev/null > /dev/null 2> $T/ld_run.txt; st_run=$?
LD_DEBUG=libs $B/rj plot $S/deploy.rjs --t-end 0.01 --out $T/ld_plot.png > /dev/null 2> $T/ld_plot.txt; st_plot=$?
ok "check and run load no OSMesa and no LLVM (LD_DEBUG=libs; status $st, $st_run), plot loads libOSMesa (status $st_plot)" \
  "[ $st = 0 ] && [ $st_run = 0 ] && [ $st_plot = 0 ] && grep -q 'calling init: .*libc\\.so' $T/ld_check.txt \
   && grep -q 'calling init: .*libc\\.so' $T/ld_run.txt && ! grep -qi -e osmesa -e libLLVM $T/ld_check.txt $T/ld_run.txt \
   && grep -q 'calling init: .*libOSMesa' $T/ld_plot.txt && [ -s $T/ld_plot.png ]"
# without OSMesa (RJ_OSMESA names the library file the renderer opens instead of
# libOSMesa.so.8): plot and animate say which library and the apt-get line, exit 1, write no image
rm -f $T/noosm.png
m 1 "^rj plot: cannot load the OSMesa library /nonexistent/libOSMesa\\.so\\.8 .*No such file.*apt-get install libosmesa6" \
  "plot without OSMesa names the library and how to install it" \
  env RJ_OSMESA=/nonexistent/libOSMesa.so.8 $B/rj plot $S/deploy.rjs --t-end 0.01 --out $T/noosm.png
ok "plot without OSMesa writes no PNG" "[ ! -e $T/noosm.png ]"
m 1 "^rj animate: cannot load the OSMesa library /nonexistent/libOSMesa\\.so\\.8 .*apt-get install libosmesa6" \
  "animate without OSMesa names the library and how to install it, before the run" \
  env RJ_OSMESA=/nonexistent/libOSMesa.so.8 $B/rj animate $S/deploy.rjs --t-end 0.01 --out $T/noosm_frames
ok "animate without OSMesa writes no frame" "[ -z \"\$(ls $T/noosm_frames 2>/dev/null)\" ]"
t 0 "check runs with RJ_OSMESA pointing nowhere: it never opens the renderer" env RJ_OSMESA=/nonexistent $B/rj check $S/deploy.rjs
# ---- --set: a change on the command line is the same edit in the file, byte for byte in
# the history; a material's reaches its links; a bad one is refused naming it
sed 's/^  length = 1.006423  elements = 10$/  length = 1.006423  elements = 10  E = 60e9/' $S/deploy.rjs > $T/set_link.rjs
sed 's/^  E = 7e10   /  E = 69e9   /' $S/deploy.rjs > $T/set_mat.rjs
$B/rj run $S/deploy.rjs --t-end 0.05 --set link.arm1.E=60e9 --csv $T/set_a.csv 2>/dev/null
$B/rj run $T/set_link.rjs --t-end 0.05 --csv $T/set_b.csv 2>/dev/null
$B/rj run $S/deploy.rjs --t-end 0.05 --csv $T/set_0.csv 2>/dev/null
ok "run --set link.arm1.E=60e9: the history of the file with E = 60e9 in link arm1, byte for byte, not the original's" \
  "grep -q 'E = 60e9' $T/set_link.rjs && cmp -s $T/set_a.csv $T/set_b.csv && ! cmp -s $T/set_a.csv $T/set_0.csv"
$B/rj run $S/deploy.rjs --t-end 0.05 --set material.alu.E=69e9 --csv $T/set_c.csv 2>/dev/null
$B/rj run $T/set_mat.rjs --t-end 0.05 --csv $T/set_d.csv 2>/dev/null
ok "run --set material.alu.E=69e9 reaches both links, as the edited material does" \
  "grep -q 'E = 69e9' $T/set_mat.rjs && cmp -s $T/set_c.csv $T/set_d.csv && ! cmp -s $T/set_c.csv $T/set_0.csv"
m 2 "^--set:1:6: the file has no link 'arm3' to change" "run --set naming a link the file does not have is refused, naming it" \
  $B/rj run $S/deploy.rjs --set link.arm3.E=1
m 2 "^--set:2:16: E = -3 is out of range in material 'alu'" "check --set with a value out of range: the change's number and the rule" \
  $B/rj check $S/deploy.rjs --set solver.dt=0 --set material.alu.E=-3
m 2 "unknown key 'fricton' in joint 'j1'; did you mean 'friction'" "check --set with a misspelt key gets did you mean" \
  $B/rj check $S/deploy.rjs --set joint.j1.fricton=0.1
# ---- rj sweep: samples of --set keys, a row each; shards join to the unsharded run byte for
# byte (every shard writes the header); sample k's values depend only on the seed and k
SW="$S/solar_array.rjs --vary joint.h1.friction=0.01:0.03 --vary material.cfrp_sandwich.rho=2400:2600 --t-end 4"
$B/rj sweep $SW --samples 6 --csv $T/sw.csv 2>$T/sw.err; st=$?
for i in 0 1 2; do $B/rj sweep $SW --samples 6 --shard $i/3 --csv $T/sw$i.csv 2>/dev/null; done
{ head -1 $T/sw0.csv; tail -q -n +2 $T/sw0.csv $T/sw1.csv $T/sw2.csv | sort -t, -k1,1n; } > $T/sw_join.csv
ok "sweep --shard 0/3, 1/3, 2/3: joined (one header, rows sorted by sample) they are the unsharded output byte for byte (status $st)" \
  "[ $st = 0 ] && [ \$(wc -l < $T/sw.csv) = 7 ] && cmp -s $T/sw.csv $T/sw_join.csv && [ \"\$(head -1 $T/sw1.csv)\" = \"\$(head -1 $T/sw.csv)\" ]"
ok "sweep header: sample, the varied keys, J.first_contact, J.lock, J.peak_pin_force per joint, L.peak_moment per flexible link, status, message" \
  "head -1 $T/sw.csv | grep -qx 'sample,joint.h1.friction,material.cfrp_sandwich.rho,h1.first_contact,h1.lock,h1.peak_pin_force,h2.first_contact,h2.lock,h2.peak_pin_force,h3.first_contact,h3.lock,h3.peak_pin_force,h4.first_contact,h4.lock,h4.peak_pin_force,hub.peak_moment,p1.peak_moment,p2.peak_moment,p3.peak_moment,p4.peak_moment,status,message'"
$B/rj sweep $SW --samples 20 --shard 4/16 --csv $T/sw_alone.csv 2>/dev/null
ok "sweep: sample 4 run alone in a sweep of 20 (--shard 4/16) is the same row as in the sweep of 6" \
  "[ \$(wc -l < $T/sw_alone.csv) = 2 ] && [ \"\$(sed -n 2p $T/sw_alone.csv)\" = \"\$(grep '^4,' $T/sw.csv)\" ]"
$B/rj sweep $SW --samples 6 --seed 2 --csv $T/sw_seed2.csv 2>/dev/null
ok "sweep --seed 2 draws other values" "! cmp -s $T/sw.csv $T/sw_seed2.csv"
ok "sweep: every hinge locks in every sample, the values within their ranges, status ok" \
  "awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if (\$i ~ /\\.lock\$/) l[++n] = i; next }
            { if (\$2 < 0.01 || \$2 > 0.03 || \$3 < 2400 || \$3 > 2600 || \$(NF - 1) != \"ok\") bad = 1
              for (i = 1; i <= n; i++) if (!(\$l[i] > 0)) bad = 1; rows++ }
            END { exit bad || n != 4 || rows != 6 }' $T/sw.csv"
# a row's values are the texts rj run --set takes: that run's summary has the same lock time
row=$(grep '^2,' $T/sw.csv); f=$(echo "$row" | cut -d, -f2); r=$(echo "$row" | cut -d, -f3); lk=$(echo "$row" | cut -d, -f5)
$B/rj run $S/solar_array.rjs --t-end 4 --set joint.h1.friction=$f --set material.cfrp_sandwich.rho=$r --csv /dev/null 2>$T/sw_run.err
lr=$(summary_times $T/sw_run.err h1 | cut -d' ' -f1)
ok "sweep: sample 2 rerun with rj run --set its values: h1 locks at the same time ($lk, rj run $lr)" \
  "awk 'BEGIN { a = \"$lk\" + 0; b = \"$lr\" + 0; exit !(a > 0 && (a - b) ^ 2 < 1e-16) }'"
ok "sweep: a summary on standard error" "grep -q '^rj sweep: 6 samples (shard 0/1), 0 not ok, wall' $T/sw.err"
# a sample whose scene the model refuses (both ends of each range load alone, not together) is
# a row with its status and message, and the sweep goes on
$B/rj sweep $S/solar_array.rjs --set solver.dt=4e-5 --vary material.cfrp_sandwich.E=70e9:90e9 \
  --vary material.cfrp_sandwich.rho=2000:2500 --samples 6 --t-end 0.001 --csv $T/sw_bad.csv 2>/dev/null; st=$?
ok "sweep: samples above the stability bound are rows with status unstable_dt and the message, the others ok (status $st)" \
  "[ $st = 0 ] && [ \$(wc -l < $T/sw_bad.csv) = 7 ] && grep -q ',unstable_dt,\"examples/scenes/solar_array.rjs:.*above the stability bound' $T/sw_bad.csv && grep -q ',ok,\"\"\$' $T/sw_bad.csv"
m 2 "^rj sweep: option --vary: bad value 'joint.h1.friction=0.01' \\(need KEY=LO:HI" "sweep --vary without ':' is refused, naming it" \
  $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0.01 --samples 2
m 2 "^rj sweep: option --vary: bad value 'joint.h1.friction=0.03:0.01' \\(need LO <= HI\\)" "sweep --vary with LO > HI is refused" \
  $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0.03:0.01 --samples 2
m 2 "^rj sweep: option --vary joint.h9.friction=0.01:0.02: at LO = 0.01: --set:1:7: the file has no joint 'h9'" \
  "sweep --vary naming a joint the file does not have is refused, naming it" \
  $B/rj sweep $S/solar_array.rjs --vary joint.h9.friction=0.01:0.02 --samples 2
m 2 "^rj sweep: option --vary joint.h1.friction=-0.01:0.02: at LO = -0.01: .*out of range" "sweep --vary with an end the file refuses" \
  $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=-0.01:0.02 --samples 2
m 2 "option --samples: bad value '0'" "sweep --samples 0 is refused" $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0:1 --samples 0
m 2 "option --shard: bad value '3/3' \\(need i/n with 0 <= i < n\\)" "sweep --shard 3/3 is refused" \
  $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0:1 --samples 3 --shard 3/3
m 2 "unknown option '--vray'; did you mean '--vary'\\?" "sweep --vray: did you mean --vary" $B/rj sweep $S/solar_array.rjs --vray x=1:2 --samples 1
m 2 "option --samples is required" "sweep without --samples is refused" $B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0:1
ok "sweep --help: the usage, within C99's 4095 characters a string; rj --help lists sweep" \
  "$B/rj sweep --help | grep -q '^usage: rj sweep SCENE.rjs --vary KEY=LO:HI' && [ \$($B/rj sweep --help | wc -c) -le 4095 ] && $B/rj --help | grep -q '^  sweep '"
# ---- rj sweep --threads, --progress, --resume, --shard auto: the rows of one thread, of an
# uninterrupted run, of --shard i/n; a file of another sweep and a shard Slurm did not give refused
$B/rj sweep $SW --samples 6 --threads 2 --progress --csv $T/sw_t2.csv 2>$T/sw_t2.err; st=$?
ok "sweep --threads 2: the same bytes as --threads 1 (status $st)" "[ $st = 0 ] && cmp -s $T/sw.csv $T/sw_t2.csv"
ok "sweep --progress: samples done, rate and ETA on standard error, ending at 6 / 6" \
  "grep -q '^rj sweep: 100.0 %  6 / 6 samples  .* samples/s  ETA 0 s\$' $T/sw_t2.err"
SWS="$S/solar_array.rjs --vary joint.h1.friction=0.01:0.03 --t-end 0.02 --samples 20"
$B/rj sweep $SWS --csv $T/sw_s1.csv 2>/dev/null
$B/rj sweep $SWS --threads 3 --csv $T/sw_s3.csv 2>/dev/null; st=$?
ok "sweep --threads 3 over 20 short samples (the ring of rows waiting for their turn wraps): --threads 1's bytes (status $st)" \
  "[ $st = 0 ] && [ \$(wc -l < $T/sw_s1.csv) = 21 ] && cmp -s $T/sw_s1.csv $T/sw_s3.csv"
# a run cut short: the header, 2 rows and half of the third, without its newline
{ head -3 $T/sw.csv; printf '%s' "$(sed -n 4p $T/sw.csv | cut -c1-30)"; } > $T/sw_cut.csv
cp $T/sw_cut.csv $T/sw_cut0.csv
$B/rj sweep $SW --samples 6 --threads 2 --resume --csv $T/sw_cut.csv 2>$T/sw_cut.err; st=$?
ok "sweep --resume after a run cut short (2 rows and half a line): the half line cut, 4 samples appended, the uninterrupted file byte for byte (status $st)" \
  "[ $st = 0 ] && [ \$(tail -c 1 $T/sw_cut0.csv | wc -l) = 0 ] && cmp -s $T/sw.csv $T/sw_cut.csv &&
   grep -q 'sw_cut.csv holds 2 of the shard.s samples; 4 to run' $T/sw_cut.err && grep -q '^rj sweep: 4 samples' $T/sw_cut.err"
$B/rj sweep $SW --samples 6 --resume --csv $T/sw_cut.csv 2>$T/sw_cut2.err; st=$?
ok "sweep --resume of a finished file runs nothing and leaves it as it was (status $st)" \
  "[ $st = 0 ] && cmp -s $T/sw.csv $T/sw_cut.csv && grep -q '^rj sweep: 0 samples' $T/sw_cut2.err"
rm -f $T/sw_new.csv
$B/rj sweep $SW --samples 6 --shard 2/3 --resume --csv $T/sw_new.csv 2>/dev/null; st=$?
ok "sweep --resume of a file that does not exist yet: the sweep from the start (status $st)" "[ $st = 0 ] && cmp -s $T/sw2.csv $T/sw_new.csv"
cp $T/sw.csv $T/sw_other.csv
$B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=0.01:0.03 --t-end 4 --samples 6 --resume --csv $T/sw_other.csv 2>$T/sw_other.err; st=$?
ok "sweep --resume with another --vary (another header) is refused showing the file's header and this sweep's, the file untouched (status $st)" \
  "[ $st = 2 ] && grep -q '^rj sweep: option --resume: the header of $T/sw_other.csv differs from this sweep' $T/sw_other.err &&
   grep -qxF \"\$(head -1 $T/sw.csv)\" $T/sw_other.err && grep -qx 'sample,joint.h1.friction,h1.first_contact,.*,status,message' $T/sw_other.err &&
   cmp -s $T/sw.csv $T/sw_other.csv"
m 2 "sw_cut0.csv:2: not a row of this sweep: sample 0's joint.h1.friction is not this sweep's" \
  "sweep --resume with another --seed: the first row's values are not this sweep's, refused naming the line" \
  $B/rj sweep $SW --samples 6 --seed 2 --resume --csv $T/sw_cut0.csv
m 2 "sw_cut0.csv:2: not a row of this sweep: sample 0 is not in shard 1/3" "sweep --resume with another --shard is refused naming the line" \
  $B/rj sweep $SW --samples 6 --shard 1/3 --resume --csv $T/sw_cut0.csv
ok "sweep --resume refused: the file is left as it was" "{ head -3 $T/sw.csv; printf '%s' \"\$(sed -n 4p $T/sw.csv | cut -c1-30)\"; } | cmp -s - $T/sw_cut0.csv"
m 2 "option --resume needs --csv FILE" "sweep --resume without --csv is refused" $B/rj sweep $SW --samples 6 --resume
SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3 $B/rj sweep $SW --samples 6 --shard auto --csv $T/sw_auto.csv 2>$T/sw_auto.err; st=$?
ok "sweep --shard auto with SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3: --shard 1/3's file byte for byte (status $st)" \
  "[ $st = 0 ] && cmp -s $T/sw1.csv $T/sw_auto.csv && grep -q '(shard 1/3)' $T/sw_auto.err"
m 2 "option --shard auto: SLURM_ARRAY_TASK_(ID|COUNT) is not set" "sweep --shard auto outside a Slurm job array is refused, naming the variable" \
  env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT $B/rj sweep $SW --samples 6 --shard auto
m 2 "option --shard auto: SLURM_ARRAY_TASK_ID=3 is not below SLURM_ARRAY_TASK_COUNT=3 \\(number the array from 0" \
  "sweep --shard auto with a task id past the count (an array not from 0) is refused" \
  env SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_COUNT=3 $B/rj sweep $SW --samples 6 --shard auto
m 2 "option --shard auto: SLURM_ARRAY_TASK_COUNT='x' is not an integer" "sweep --shard auto with a malformed task count is refused" \
  env SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=x $B/rj sweep $SW --samples 6 --shard auto
m 2 "option --threads: bad value '0'" "sweep --threads 0 is refused" $B/rj sweep $SW --samples 6 --threads 0
# ---- rj plot --what sweep: a sweep's rows drawn (lock times and peak pin forces as
# histograms, one column against another, the share latched), no golden image: the PNG's
# size, and pixels of each joint's colour (the palette's first 4) and of ink in it
$B/rj sweep $S/solar_array.rjs --vary joint.h1.friction=normal:0.02:0.003 --vary material.cfrp_sandwich.rho=2250:2750 \
  --lhs --samples 8 --t-end 3 --csv $T/sw_plot.csv 2>/dev/null
$B/rj plot --what sweep --csv $T/sw_plot.csv --size 640x480 --out $T/sw_plot.png 2>$T/sw_plot.err; st=$?
# width and height from the PNG's IHDR (bytes 17..24, big-endian)
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{ printf "%dx%d", (($1 * 256 + $2) * 256 + $3) * 256 + $4, (($5 * 256 + $6) * 256 + $7) * 256 + $8 }'; }
ok "plot --what sweep: a 640x480 PNG of 8 rows (status $st), the count on standard error" \
  "[ $st = 0 ] && [ '$(magic $T/sw_plot.png)' = 89504e47 ] && [ '$(png_size $T/sw_plot.png)' = 640x480 ] \
   && grep -q '^rj plot: $T/sw_plot.csv: 8 rows, 8 ok, 4 joints drawn\$' $T/sw_plot.err"
if [ -x /usr/bin/python3 ]; then
  set -- $(/usr/bin/python3 tools/png_count.py $T/sw_plot.png 1f77b4 d62728 2ca02c ff7f0e)
  ok "plot --what sweep: not blank ($1 of 307200 pixels not white) and each joint's colour drawn ($2, $3, $4, $5 pixels)" \
    "[ '$1' -gt 15000 ] && [ '$2' -gt 100 ] && [ '$3' -gt 100 ] && [ '$4' -gt 100 ] && [ '$5' -gt 100 ]"
else echo "SKIP rj: no /usr/bin/python3 to count the sweep plot's pixels"; fi
# a failed row is left out and counted; the scatter's columns may be any number column,
# a varied key named with or without its [unit]
# (the sample, 2 values, 17 empty numbers: 4 joints x 3 and 5 links)
{ cat $T/sw_plot.csv; printf '8,0.5,2500%s,parse,"x, ""quoted"""\n' "$(printf ',%.0s' $(seq 17))"; } > $T/sw_plot_bad.csv
$B/rj plot --what sweep --csv $T/sw_plot_bad.csv --x material.cfrp_sandwich.rho --y h4.peak_pin_force --out $T/sw_plot2.png 2>$T/sw_plot2.err; st=$?
ok "plot --what sweep: a row that is not ok (its message quoted, with a comma) is left out and counted; --x and --y choose the scatter (status $st)" \
  "[ $st = 0 ] && grep -q ': 9 rows, 8 ok, 4 joints drawn\$' $T/sw_plot2.err && [ -s $T/sw_plot2.png ]"
$B/rj sweep $S/solar_array.rjs --vary joint.h1.angle0=85:95deg --grid 2 --t-end 0 --csv $T/sw_unit.csv 2>/dev/null
t 0 "plot --what sweep --x joint.h1.angle0: the column joint.h1.angle0[deg]" \
  $B/rj plot --what sweep --csv $T/sw_unit.csv --x joint.h1.angle0 --size 320x240 --out $T/sw_unit.png
m 2 "option --y: .* has no number column 'h1.lok'; did you mean 'h1.lock'\\?" "plot --what sweep --y h1.lok: did you mean h1.lock" \
  $B/rj plot --what sweep --csv $T/sw_plot.csv --y h1.lok --out $T/x.png
m 2 "option --what sweep needs --csv ROWS.csv" "plot --what sweep without --csv is refused" $B/rj plot --what sweep --out $T/x.png
m 2 "option --what sweep draws --csv ROWS.csv and runs no scene: unexpected argument" "plot --what sweep with a scene is refused" \
  $B/rj plot $S/deploy.rjs --what sweep --csv $T/sw_plot.csv --out $T/x.png
m 2 "option --csv is for --what sweep" "plot --csv without --what sweep is refused" $B/rj plot $S/deploy.rjs --csv $T/sw_plot.csv --out $T/x.png
m 2 "option --csv: $S/deploy.rjs is not the rows of rj sweep" "plot --what sweep of a file that is not a sweep's is refused" \
  $B/rj plot --what sweep --csv $S/deploy.rjs --out $T/x.png
m 2 "option --what: unknown value 'swep'; did you mean 'sweep'\\?" "plot --what swep: did you mean 'sweep'" \
  $B/rj plot --what swep --csv $T/sw_plot.csv --out $T/x.png
# ---- fidelity = pieces: deploy_pieces.rjs is build/deploy --links pieces's model (10 rigid
# pieces a link, bending springs E I / l): joint 2 locks within 0.01 s of it (the same step:
# the same time, printed to 6 digits), and rj check lists the pieces and the springs
$B/rj run $S/deploy_pieces.rjs --t-end 6 --csv /dev/null 2>$T/pieces.err; st=$?
$B/deploy --links pieces --t-end 6 --csv /dev/null 2>$T/pieces_deploy.err
set -- $(summary_times $T/pieces.err j2)
lib=$(tail -1 $T/pieces_deploy.err | sed -n 's/.*joint 2 at \([0-9.]*\) s.*/\1/p')
ok "run deploy_pieces.rjs --t-end 6: j2 locks at ${1:-none} s, within 0.01 s of build/deploy --links pieces's ${lib:-none} s (status $st)" \
  "[ $st = 0 ] && [ -n '$1' ] && [ -n '$lib' ] && awk 'BEGIN { d = $1 - $lib; exit !(d < 0.01 && d > -0.01) }'"
$B/rj check $S/deploy_pieces.rjs > $T/pieces_check.txt 2>&1
ok "check deploy_pieces.rjs: 22 rigid links (arm1 .. arm1_p10, arm2 .. arm2_p10) and 22 joints (j1, arm1_b1 .. arm1_b10, j2, arm2_b1 ..)" \
  "grep -qx 'links: 22, 44 nodes' $T/pieces_check.txt && grep -Eq '^  arm1_p10 +rigid +1 elements' $T/pieces_check.txt \
   && grep -Eq '^  arm2 +rigid ' $T/pieces_check.txt && grep -qx 'joints: 22' $T/pieces_check.txt \
   && grep -Eq '^  arm1_b10 +arm1_p9 -> arm1_p10, starts at 180 deg: spring 204.565 N m/rad free at 180 deg\$' $T/pieces_check.txt \
   && grep -Eq '^  j2 +arm1_p10 -> arm2, ' $T/pieces_check.txt"
# rj run watches every step without asking for the energy accounts there: with
# solver.energy_every 16 its rows (the accounts among them) and its summary are those of
# every step's accounts, byte for byte (the summary less its wall time), on a flexible and
# a rigid scene, --settle too
for f in deploy deploy_pieces; do
  $B/rj run $S/$f.rjs --set solver.energy_every=1 --t-end 0.3 --sample 0.007 --csv $T/ee1_$f.csv 2>$T/ee1_$f.err
  $B/rj run $S/$f.rjs --set solver.energy_every=16 --t-end 0.3 --sample 0.007 --csv $T/ee16_$f.csv 2>$T/ee16_$f.err
  ok "run $f.rjs: energy_every 16 and 1 give the same rows and summary ($(wc -l < $T/ee1_$f.csv) rows)" \
    "[ -s $T/ee1_$f.csv ] && cmp -s $T/ee1_$f.csv $T/ee16_$f.csv && [ \"\$(grep -v ' wall ' $T/ee1_$f.err)\" = \"\$(grep -v ' wall ' $T/ee16_$f.err)\" ]"
done
$B/rj run $S/elastica.rjs --settle --set solver.energy_every=1 --t-end 0.01 --sample 0.003 --csv $T/ee1_settle.csv 2>/dev/null
$B/rj run $S/elastica.rjs --settle --set solver.energy_every=16 --t-end 0.01 --sample 0.003 --csv $T/ee16_settle.csv 2>/dev/null
ok "run elastica.rjs --settle: energy_every 16 and 1 give the same rows, from the settled time on" \
  "[ -s $T/ee1_settle.csv ] && cmp -s $T/ee1_settle.csv $T/ee16_settle.csv"
exit 0
