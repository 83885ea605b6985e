#!/bin/sh
# Example programs: unknown options and malformed values print usage and exit with status 2.
B=${1:-build}
t() { # expected status, description, command...
  want=$1; shift; what=$1; shift
  out=$("$@" 2>&1 >/dev/null); st=$?
  if [ "$st" = "$want" ] && { [ "$want" != 2 ] || echo "$out" | grep -q usage; }; then echo "PASS cli: $what (status $st)"; else echo "FAIL cli: $what: status $st, want $want: $out"; fi
}
t 2 "impact rejects an unknown option" $B/impact --bogus
t 2 "impact rejects a malformed number" $B/impact --dt 1e-6x
t 2 "impact rejects a negative step" $B/impact --dt -1e-6
t 2 "impact rejects an unknown method" $B/impact --method magic
t 2 "impact rejects NaN" $B/impact --K nan
t 2 "deploy rejects zero elements" $B/deploy --elements 0
t 2 "deploy rejects a missing value" $B/deploy --dt
t 2 "animate rejects an unknown scene" $B/animate --scene nowhere
t 1 "impact refuses a step above the stability bound (clear error, status 1)" $B/impact --dt 15e-6
