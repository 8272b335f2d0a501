#!/bin/sh
# The layers' direction is enforced by the build: each layer compiles with only
# its own include paths (Makefile: CORE_INC, CONFIG_INC, INSTR_INC, IO_INC),
# in the order base <- core <- config <- instruments <- io <- programs. This checks
# that it is so: a core file that includes a config, binding, instrument or
# I/O header (the CSV writer among them), a config file that includes an
# instrument or I/O header, an instrument that includes an I/O header, or the
# core's internal headers from outside it, fails to compile, while the same
# include compiles in the layer that owns the header and in those above it
# (so the check is not passing for some unrelated reason).
set -u
: "${CC:?}" "${CPPFLAGS:?}" "${CORE_INC:?}" "${CONFIG_INC:?}" "${INSTR_INC:?}" "${IO_INC:?}"
T=$(mktemp -d "${TMPDIR:-/tmp}/cblayers.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
try() { # try FLAGS HEADER -> 0 if a file including HEADER compiles with FLAGS
  printf '#include %s\nint cb_layer_probe(void);\nint cb_layer_probe(void) { return 0; }\n' "$2" > "$T/probe.c"
  # shellcheck disable=SC2086
  $CC $CPPFLAGS $1 -std=c11 -c "$T/probe.c" -o "$T/probe.o" 2>/dev/null
}
expect() { # expect ok|fail LAYER FLAGS HEADER
  n=$((n + 1))
  if try "$3" "$4"; then got=ok; else got=fail; fi
  [ "$got" = "$1" ] || { echo "layers: $2 including $4: expected $1, got $got"; fail=1; }
}
for h in '"config.h"' '"bind.h"' '<clothbench/config.h>'; do
  expect fail core "$CORE_INC" "$h"
done
for h in '"config.h"' '"bind.h"'; do
  expect ok config "$CONFIG_INC" "$h"
  expect ok instruments "$INSTR_INC" "$h"
  expect ok io "$IO_INC" "$h"
done
for h in '"capture.h"' '"stats.h"' '"reference.h"' '"stability.h"' '"thread_probe.h"'; do
  expect fail core "$CORE_INC" "$h"
  expect fail config "$CONFIG_INC" "$h"
  expect ok instruments "$INSTR_INC" "$h"
  expect ok io "$IO_INC" "$h"
done
for h in '"outfile.h"' '"experiment.h"' '"provenance.h"' '"progress.h"' '"csv.h"'; do
  expect fail core "$CORE_INC" "$h"
  expect fail config "$CONFIG_INC" "$h"
  expect fail instruments "$INSTR_INC" "$h"
  expect ok io "$IO_INC" "$h"
done
expect fail instruments "$INSTR_INC" '"solver_iterative.h"'
expect ok core "$CORE_INC" '"solver_iterative.h"'
expect ok core "$CORE_INC" '<clothbench/clothbench.h>'
# lib/base/ (header-only vec.h, rng.h) sits below the core: every layer reaches
# it, and it reaches nothing of the project (it compiles on its own path alone)
for h in '"vec.h"' '"rng.h"'; do
  expect ok base "-Ilib/base" "$h"
  expect ok core "$CORE_INC" "$h"
done
expect fail base "-Ilib/base" '<clothbench/mesh.h>'
expect fail base "-Ilib/base" '"mesh.h"'
[ $fail = 0 ] && echo "layers: ok ($n include checks: base reaches nothing of the project; core cannot reach config, instruments or I/O (CSV writing included); config cannot reach instruments or I/O; instruments cannot reach I/O; I/O reaches instruments)"
exit $fail
