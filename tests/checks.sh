# checks.sh - the command-line checks shared by tests/cli.sh and tests/rj.sh, sourced after
# setting P (the prefix of their PASS/FAIL lines). Each prints one PASS or FAIL line.
# status, description, command...: the status, and the usage text after a status 2
t() {
  want=$1; shift; what=$1; shift
  out=$("$@" 2>&1 >/dev/null); st=$?
  if [ "$st" = "$want" ] && { [ "$want" != 2 ] || echo "$out" | grep -q usage; }; then echo "PASS $P: $what (status $st)"
  else echo "FAIL $P: $what: status $st, want $want: $out"; fi
}
# status, pattern the messages must match (grep -E), description, command...
m() {
  want=$1; shift; pat=$1; shift; what=$1; shift
  out=$("$@" 2>&1 >/dev/null); st=$?
  if [ "$st" = "$want" ] && printf '%s\n' "$out" | grep -Eq -- "$pat"; then echo "PASS $P: $what (status $st)"
  else echo "FAIL $P: $what: status $st, want $want and a message matching /$pat/: $out"; fi
}
# description, condition (a shell command that must succeed)
ok() {
  if sh -c "$2"; then echo "PASS $P: $1"; else echo "FAIL $P: $1"; fi
}
