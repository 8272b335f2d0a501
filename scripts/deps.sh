#!/bin/sh
# Checks for the Debian packages clothbench builds against and installs the
# missing ones (apt-get update first) when run as root. Otherwise it prints the
# one command to run and fails, so `make test` stops before compiling.
# Arguments name packages that one target needs besides these (make fuzz: clang;
# make bench: python3-scipy).
set -u
PKGS="libgsl-dev libsuitesparse-dev libopenblas-dev libinih-dev libcriterion-dev libgmp-dev libembree-dev gnuplot-nox libpetsc-real-dev $*"
missing=""
for p in $PKGS; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0
cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends$missing"
if [ "$(id -u)" = 0 ]; then
  echo "deps: installing$missing" >&2
  sh -c "$cmd" || { echo "deps: apt-get failed; run by hand: $cmd" >&2; exit 1; }
  exit 0
fi
if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  echo "deps: installing$missing with sudo" >&2
  sudo sh -c "$cmd" || { echo "deps: apt-get failed; run by hand: sudo sh -c '$cmd'" >&2; exit 1; }
  exit 0
fi
echo "deps: missing Debian packages:$missing" >&2
echo "deps: run this, then re-run make:" >&2
echo "  sudo sh -c '$cmd'" >&2
exit 1
