#!/bin/sh
# Installs the system packages the build and the tests need when they are missing and we
# are root on a Debian-like system; otherwise stops with the exact command to run.
need=""
command -v pkg-config >/dev/null 2>&1 || need="$need pkg-config"
command -v cc >/dev/null 2>&1 || command -v gcc >/dev/null 2>&1 || need="$need gcc libc6-dev"
command -v g++ >/dev/null 2>&1 || need="$need g++"
command -v clang >/dev/null 2>&1 || need="$need clang"
command -v make >/dev/null 2>&1 || need="$need make"
# tests/sweep.sh splits an rj sweep over shards run by GNU parallel, as a cluster would
command -v parallel >/dev/null 2>&1 || need="$need parallel"
# the elastica's reference (tests/elastica_ref.py) solves its boundary-value problem with scipy
/usr/bin/python3 -c "import numpy, scipy" >/dev/null 2>&1 || need="$need python3-numpy python3-scipy"
if command -v pkg-config >/dev/null 2>&1; then
  pkg-config --exists osmesa 2>/dev/null || need="$need libosmesa6-dev"
  pkg-config --exists libpng 2>/dev/null || need="$need libpng-dev"
else
  need="$need libosmesa6-dev libpng-dev"
fi
[ -z "$need" ] && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "deps: installing$need" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends $need >/dev/null || {
    echo "deps: apt-get install failed; run: apt-get update && apt-get install -y$need" >&2; exit 1; }
  exit 0
fi
echo "deps: missing packages. Run:" >&2
echo "  sudo apt-get update && sudo apt-get install -y$need" >&2
exit 1
