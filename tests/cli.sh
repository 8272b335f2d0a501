#!/bin/sh
# End-to-end checks of build/simulate as a user runs it.
#
# Run from the repository root (make check does: BUILD=<dir> tests/cli.sh).
# Every check prints what failed; the script exits non-zero if any failed.
set -u

B=${BUILD:-build}
ROOT=$(pwd)
SIM=$ROOT/$B/simulate
case $B in /*) SIM=$B/simulate ;; esac
CONFIG=$ROOT/configs/hanging.ini

if [ ! -x "$SIM" ]; then
  echo "cli: FAIL: $SIM not found or not executable (build it first)"
  exit 1
fi
if [ ! -f "$CONFIG" ]; then
  echo "cli: FAIL: $CONFIG not found (run from the repository root)"
  exit 1
fi

T=$(mktemp -d "${TMPDIR:-/tmp}/cbcli.XXXXXX") || { echo "cli: FAIL: mktemp"; exit 1; }
trap 'rm -rf "$T"' EXIT INT TERM

failures=0
checks=0

fail() {
  echo "cli: FAIL: $*"
  failures=$((failures + 1))
}

# check DESCRIPTION COMMAND...: runs a test command, records a failure if it is false
check() {
  desc=$1
  shift
  checks=$((checks + 1))
  if ! "$@"; then fail "$desc"; fi
}

# sim NAME ARGS...: runs simulate with stdout/stderr in $T/NAME.out/.err; rc in $rc
sim() {
  name=$1
  shift
  "$SIM" "$@" >"$T/$name.out" 2>"$T/$name.err"
  rc=$?
}

expect_rc() { # NAME WANT
  checks=$((checks + 1))
  if [ "$rc" -ne "$2" ]; then
    fail "$1: exit code $rc, expected $2; stderr:"
    sed 's/^/    /' "$T/$1.err" | head -n 20
  fi
}

expect_err() { # NAME FIXED-STRING: stderr of run NAME contains the string
  checks=$((checks + 1))
  if ! grep -Fq -- "$2" "$T/$1.err"; then
    fail "$1: stderr does not mention '$2'; stderr:"
    sed 's/^/    /' "$T/$1.err" | head -n 20
  fi
}

data_rows() { grep -v '^#' "$1" | tail -n +2; }          # CSV rows after the header
header_of() { grep -v '^#' "$1" | head -n 1; }           # CSV header row
last_field() { data_rows "$1" | tail -n 1 | awk -F, -v c="$(col "$1" status)" '{print $c}'; } # the last row's status

# col FILE NAME: the 1-based index of column NAME in the CSV header
col() { header_of "$1" | tr ',' '\n' | grep -nx -- "$2" | cut -d: -f1; }

# ---- a normal run: configs/hanging.ini --steps 60 ------------------------------------

sim hang "$CONFIG" --steps 60 --csv "$T/hang/out.csv" --obj "$T/hang/out.obj"
expect_rc hang 0
check "hang: CSV written (into a directory that did not exist)" test -s "$T/hang/out.csv"
check "hang: OBJ written" test -s "$T/hang/out.obj"
if [ -s "$T/hang/out.csv" ]; then
  csv=$T/hang/out.csv
  n=$(data_rows "$csv" | wc -l | tr -d ' ')
  check "hang: $n data rows, expected 61 (step 0 and 60 steps)" test "$n" -eq 61
  hdr=$(header_of "$csv")
  case $hdr in
    step,t_s,kinetic_j,elastic_j,gravity_j,total_j,pin_work_j,*,status,contacts,rho) : ;;
    *) fail "hang: header '$hdr' does not run step,t_s,kinetic_j,elastic_j,gravity_j,total_j,pin_work_j,...,status,contacts,rho" ;;
  esac
  checks=$((checks + 1))
  for c in step t_s kinetic_j elastic_j gravity_j total_j pin_work_j newton_iters wall_ms status contacts; do
    check "hang: header lacks column $c" test -n "$(col "$csv" "$c")"
  done
  # the provenance block: every line before the header starts with '#'
  pre=$(awk '/^#/ {next} {print NR; exit}' "$csv")
  check "hang: no provenance lines before the header" test "${pre:-1}" -gt 1
  bad=$(head -n $((${pre:-1} - 1)) "$csv" | grep -vc '^#')
  check "hang: a line before the header does not start with '#'" test "$bad" -eq 0
  check "hang: provenance lacks '# git_revision:'" grep -q '^# git_revision:' "$csv"
  check "hang: provenance lacks '# config:'" grep -q '^# config:' "$csv"
  check "hang: provenance lacks '# blas_threads:'" grep -q '^# blas_threads:' "$csv"
  check "hang: provenance lacks '# threads_observed:'" grep -q '^# threads_observed: cholmod_factorize [0-9]' "$csv"
  check "hang: provenance lacks '# blas_kernel:'" grep -q '^# blas_kernel: [A-Za-z]' "$csv"
  check "hang: provenance lacks how the kernel was chosen" grep -Eq '^# blas_kernel_choice: (detected|set by the environment|chosen|refused)' "$csv"
  check "hang: a '#' line after the header" test "$(grep -v '^#' "$csv" | grep -c '^#')" -eq 0
  # every row has as many fields as the header
  nf=$(echo "$hdr" | awk -F, '{print NF}')
  badrows=$(data_rows "$csv" | awk -F, -v nf="$nf" 'NF != nf' | wc -l | tr -d ' ')
  check "hang: $badrows rows with a field count other than $nf" test "$badrows" -eq 0
  # steps 0..60 in order, t_s = step/30, statuses ok (or max_iters, not fatal)
  sc=$(col "$csv" step)
  tc=$(col "$csv" t_s)
  badsteps=$(data_rows "$csv" | awk -F, -v s="$sc" -v t="$tc" \
    '{ if ($s != NR - 1) print; d = $t - (NR - 1) / 30; if (d < -1e-12 || d > 1e-12) print }' | wc -l | tr -d ' ')
  check "hang: $badsteps rows with a wrong step or t_s" test "$badsteps" -eq 0
  badstat=$(data_rows "$csv" | awk -F, -v c="$(col "$csv" status)" '$c != "ok" && $c != "max_iters"' | wc -l | tr -d ' ')
  check "hang: $badstat rows with a fatal status" test "$badstat" -eq 0
  # the cloth falls: the gravity potential at the end is below the start
  pc=$(col "$csv" gravity_j)
  fell=$(data_rows "$csv" | awk -F, -v p="$pc" 'NR == 1 {p0 = $p} END {print ($p < p0 - 1) ? 1 : 0}')
  check "hang: gravity potential did not decrease" test "$fell" -eq 1
  # each energy column holds one thing: kinetic + elastic + gravity = total (potential_j held elastic too)
  kc=$(col "$csv" kinetic_j); ec=$(col "$csv" elastic_j); tc=$(col "$csv" total_j)
  badsum=$(data_rows "$csv" | awk -F, -v k="$kc" -v e="$ec" -v g="$pc" -v t="$tc" \
    '{ d = $k + $e + $g - $t; s = ($t < 0 ? -$t : $t) + 1; if (d > 1e-9 * s || d < -1e-9 * s) print }' | wc -l | tr -d ' ')
  check "hang: $badsum rows where kinetic_j + elastic_j + gravity_j != total_j" test "$badsum" -eq 0
fi
if [ -s "$T/hang/out.obj" ]; then
  nv=$(grep -c '^v ' "$T/hang/out.obj")
  nf=$(grep -c '^f ' "$T/hang/out.obj")
  check "hang: OBJ has $nv vertices, expected 441" test "$nv" -eq 441
  check "hang: OBJ has $nf faces, expected 800" test "$nf" -eq 800
  # the pinned top corners (vertices 421 and 441, 1-based) stay at z = 5, x = -5 and 5
  pin=$(grep '^v ' "$T/hang/out.obj" | awk 'NR == 421 || NR == 441 {
          ex = (NR == 421) ? -5 : 5; if (($2 - ex)^2 + $3^2 + ($4 - 5)^2 > 1e-20) bad++ } END {print bad + 0}')
  check "hang: pinned corners moved" test "$pin" -eq 0
fi

# ---- --steps 0 writes the initial mesh ---------------------------------------------------

sim zero "$CONFIG" --steps 0 --quiet --csv "$T/zero.csv" --obj "$T/zero.obj"
expect_rc zero 0
if [ -s "$T/zero.csv" ] && [ -s "$T/zero.obj" ]; then
  check "zero: CSV should have exactly one row (step 0)" test "$(data_rows "$T/zero.csv" | wc -l | tr -d ' ')" -eq 1
  check "zero: row 0 should be step 0" test "$(data_rows "$T/zero.csv" | cut -d, -f1)" = 0
  check "zero: OBJ vertex count" test "$(grep -c '^v ' "$T/zero.obj")" -eq 441
  # the 21 x 21 grid on 10 m x 10 m in the xz plane: vertex (i, j) = (-5 + i/2, 0, -5 + j/2)
  off=$(grep '^v ' "$T/zero.obj" | awk '{ k = NR - 1; i = k % 21; j = int(k / 21);
          d = ($2 - (-5 + i / 2))^2 + $3^2 + ($4 - (-5 + j / 2))^2; if (d > 1e-20) bad++ } END {print bad + 0}')
  check "zero: $off OBJ vertices differ from the initial grid" test "$off" -eq 0
else
  fail "zero: CSV or OBJ missing"
fi
check "zero: --quiet still printed to stderr" test ! -s "$T/zero.err"

# default output paths: results/<config name>.csv and .obj, relative to the working directory
mkdir -p "$T/cwd"
(cd "$T/cwd" && "$SIM" "$CONFIG" --steps 1 --quiet >"$T/cwd.out" 2>"$T/cwd.err")
rc=$?
expect_rc cwd 0
check "default paths: results/hanging.csv not written" test -s "$T/cwd/results/hanging.csv"
check "default paths: results/hanging.obj not written" test -s "$T/cwd/results/hanging.obj"

# ---- bad input: exit 1, with file:line and the key ------------------------------------

printf '[mesh]\nn = 5\nsides = 4\n' >"$T/bad_key.ini"
sim bad_key "$T/bad_key.ini" --csv "$T/bad_key.csv" --obj "$T/bad_key.obj"
expect_rc bad_key 1
expect_err bad_key "bad_key.ini:3"
expect_err bad_key "mesh.sides"
check "bad_key: a CSV was written for a config that does not load" test ! -e "$T/bad_key.csv"

printf '; dt must be positive\n[integrator]\nmethod = newton\ndt = -1\n' >"$T/bad_value.ini"
sim bad_value "$T/bad_value.ini" --csv "$T/bad_value.csv" --obj "$T/bad_value.obj"
expect_rc bad_value 1
expect_err bad_value "bad_value.ini:4"
expect_err bad_value "integrator.dt"

printf '[mesh]\nplane = xw\n' >"$T/bad_enum.ini"
sim bad_enum "$T/bad_enum.ini" --csv "$T/bad_enum.csv" --obj "$T/bad_enum.obj"
expect_rc bad_enum 1
expect_err bad_enum "bad_enum.ini:2"
expect_err bad_enum "mesh.plane"

printf '[scene]\npins = 0 9999\n' >"$T/bad_pins.ini"
sim bad_pins "$T/bad_pins.ini" --csv "$T/bad_pins.csv" --obj "$T/bad_pins.obj"
expect_rc bad_pins 1
expect_err bad_pins "scene.pins"

sim missing "$T/no-such-config.ini" --csv "$T/missing.csv"
expect_rc missing 1
expect_err missing "no-such-config.ini"

sim unknown_opt "$CONFIG" --frobnicate --csv "$T/u.csv" --obj "$T/u.obj"
expect_rc unknown_opt 1
expect_err unknown_opt "--frobnicate"

sim set_unknown "$CONFIG" --set material.nope=1 --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc set_unknown 1
expect_err set_unknown "material.nope"

sim set_range "$CONFIG" --set mesh.n=1 --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc set_range 1
expect_err set_range "mesh.n"

sim set_noeq "$CONFIG" --set mesh.n --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc set_noeq 1

sim set_noval "$CONFIG" --set
expect_rc set_noval 1

sim steps_neg "$CONFIG" --steps -3 --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc steps_neg 1
sim steps_word "$CONFIG" --steps ten --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc steps_word 1

sim no_config
expect_rc no_config 1

sim two_configs "$CONFIG" "$CONFIG" --csv "$T/s.csv" --obj "$T/s.obj"
expect_rc two_configs 1

check "bad input runs wrote $T/s.csv" test ! -e "$T/s.csv"

# an output path that cannot be created: exit 2
: >"$T/plainfile"
sim unwritable "$CONFIG" --steps 1 --quiet --csv "$T/plainfile/sub/out.csv" --obj "$T/uw.obj"
expect_rc unwritable 2

# ---- numerical failures: exit 3 (diverged) and 4 (not SPD), CSV kept ---------------------

sim diverge "$CONFIG" --quiet --set integrator.method=explicit --set integrator.dt=0.05 \
  --csv "$T/diverge.csv" --obj "$T/diverge.obj"
expect_rc diverge 3
expect_err diverge diverged
if [ -s "$T/diverge.csv" ]; then
  check "diverge: last CSV status is '$(last_field "$T/diverge.csv")', expected diverged" \
    test "$(last_field "$T/diverge.csv")" = diverged
  nd=$(data_rows "$T/diverge.csv" | wc -l | tr -d ' ')
  check "diverge: only the last row may be diverged" \
    test "$(data_rows "$T/diverge.csv" | head -n $((nd - 1)) | grep -c ',diverged$')" -eq 0
else
  fail "diverge: no CSV written"
fi
check "diverge: no OBJ written" test -s "$T/diverge.obj"

sim notspd "$CONFIG" --quiet --set integrator.definiteness=none --set scene.initial_scale=0.5 \
  --csv "$T/notspd.csv" --obj "$T/notspd.obj"
expect_rc notspd 4
expect_err notspd not_spd
if [ -s "$T/notspd.csv" ]; then
  check "notspd: last CSV status is '$(last_field "$T/notspd.csv")', expected not_spd" \
    test "$(last_field "$T/notspd.csv")" = not_spd
else
  fail "notspd: no CSV written"
fi

# ---- no temporary files left anywhere --------------------------------------------------

left=$(find "$T" -name '*.tmp.*' | head -n 5)
check "temporary files left behind: $left" test -z "$left"

# ---- --help and --help-config -----------------------------------------------------------

sim help --help
expect_rc help 0
for opt in --set --steps --csv --obj --quiet --help --help-config; do
  check "--help does not mention $opt" grep -Fq -- "$opt" "$T/help.out"
done
for code in 0 1 2 3 4; do
  check "--help does not document exit code $code" grep -Eq "(^|[^0-9])$code [a-z]" "$T/help.out"
done

# the thread knob: a malformed count is an error naming the variable
OMP_NUM_THREADS=two sim badomp "$CONFIG" --steps 1 --csv "$T/badomp.csv"
expect_rc badomp 1
expect_err badomp "OMP_NUM_THREADS='two'"
OPENBLAS_NUM_THREADS=0 sim badblas "$CONFIG" --steps 1 --csv "$T/badblas.csv"
expect_rc badblas 1
expect_err badblas "OPENBLAS_NUM_THREADS='0'"
# one thread requested: one thread observed in CHOLMOD's factorisation and in dgemm
OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 sim onethread "$CONFIG" --steps 1 --csv "$T/onethread.csv"
expect_rc onethread 0
check "THREADS=1: provenance does not show one observed thread" \
  grep -q '^# threads_observed: cholmod_factorize 1, dgemm 1 ' "$T/onethread.csv"

# Chebyshev as a new user tries it: no key but the method (alpha = auto, rho = auto)
sim cheb "$CONFIG" --set solver.method=chebyshev --steps 10 --csv "$T/cheb.csv"
expect_rc cheb 0
check "chebyshev with the default keys: a step did not end ok" test "$(data_rows "$T/cheb.csv" | awk -F, -v c="$(col "$T/cheb.csv" status)" '$c != "ok"' | wc -l)" -eq 0

sim helpcfg --help-config
expect_rc helpcfg 0
for key in mesh.type mesh.n mesh.m mesh.size mesh.plane mesh.diagonal mesh.file \
  material.density material.vertex_mass material.stretch_k material.bend material.bend_k \
  scene.gravity scene.pins scene.initial_scale \
  integrator.method integrator.dt integrator.steps integrator.max_iters integrator.tol \
  integrator.tol_dx integrator.definiteness integrator.init integrator.line_search integrator.diverge_ratio \
  solver.method solver.tol solver.max_iters solver.alpha solver.rho solver.ordering solver.nrelax solver.storage solver.denormals; do
  check "--help-config lacks $key" grep -Fq -- "| \`$key\` |" "$T/helpcfg.out"
done

if [ -f "$ROOT/docs/config.md" ]; then
  missing=0
  while IFS= read -r line; do
    case $line in
      '| `'*)
        if ! grep -Fxq -- "$line" "$ROOT/docs/config.md"; then
          fail "docs/config.md lacks the --help-config row: $line"
          missing=$((missing + 1))
        fi
        ;;
    esac
  done <"$T/helpcfg.out"
  checks=$((checks + 1))
else
  echo "cli: notice: docs/config.md does not exist yet; skipping the config-reference check"
fi

# ---- provenance cannot be forged: newlines in a --set value or a config filename ----

nl='
'
forged_cfg="$T/forged${nl}step,t_s: forged.ini"
cp "$CONFIG" "$forged_cfg"
sim forged "$forged_cfg" --steps 0 --set "mesh.file=x${nl}0,0,forged${nl}" --csv "$T/forged.csv" --obj "$T/forged.obj"
expect_rc forged 0
if [ -s "$T/forged.csv" ]; then
  # every line before the header row is a '#' comment, and the header is the real one
  pre=$(awk '/^#/ { next } { print NR; exit }' "$T/forged.csv")
  check "forged: the first non-comment line is the header" test "$(sed -n "${pre}p" "$T/forged.csv" | cut -d, -f1)" = step
  check "forged: one data row (--steps 0) after the header" test "$(data_rows "$T/forged.csv" | wc -l)" -eq 1
  check "forged: the newline is written escaped" grep -Fq 'mesh.file=x\n0,0,forged\n' "$T/forged.csv"
  check "forged: the config path is written escaped" grep -Fq 'forged\nstep,t_s: forged.ini' "$T/forged.csv"
else
  fail "forged: no CSV written"
fi

# ---- numeric arguments are parsed strictly, as config values are ---------------------

for bad in 4294967297 3000000000 "" -1 1.5 2x; do
  sim steps_bad "$CONFIG" --steps "$bad" --csv "$T/steps_bad.csv" --obj "$T/steps_bad.obj"
  expect_rc steps_bad 1
  expect_err steps_bad "--steps '$bad'"
  check "steps '$bad': nothing written" test ! -e "$T/steps_bad.csv"
done

# ---- outputs: devices are written into, never replaced; inputs are never overwritten ----

sim devnull "$CONFIG" --steps 2 --csv /dev/null --obj "$T/devnull.obj"
expect_rc devnull 0
check "devnull: /dev/null is still a character device" test -c /dev/null
check "devnull: the OBJ was written" test -s "$T/devnull.obj"
"$SIM" "$CONFIG" --steps 1 --csv - --obj "$T/stdout.obj" >"$T/stdout.out" 2>"$T/stdout.err"
rc=$?
expect_rc stdout 0
check "stdout: --csv - streams the CSV (header and 2 rows) to standard output" test "$(grep -vc '^#' "$T/stdout.out")" -eq 3
expect_err stdout "wrote standard output and $T/stdout.obj"
sim same "$CONFIG" --steps 1 --csv "$T/same.out" --obj "$T/same.out"
expect_rc same 1
expect_err same "is the OBJ output (--obj); refusing to overwrite it"
cp "$CONFIG" "$T/cfgcopy.ini"
sim overcfg "$T/cfgcopy.ini" --steps 1 --csv "$T/../$(basename "$T")/cfgcopy.ini" --obj "$T/overcfg.obj"
expect_rc overcfg 1
expect_err overcfg "is the config file; refusing to overwrite it"
check "overcfg: the config is untouched" cmp -s "$CONFIG" "$T/cfgcopy.ini"
printf '[mesh]\ntype = obj\nfile = quad.obj\n[material]\nvertex_mass = 1\n[scene]\npins = 0\n' > "$T/meshcfg.ini"
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n' > "$T/quad.obj"
cp "$T/quad.obj" "$T/quad.keep"
sim overmesh "$T/meshcfg.ini" --steps 1 --csv "$T/overmesh.csv" --obj "$T/quad.obj"
expect_rc overmesh 1
expect_err overmesh "is the mesh file (mesh.file); refusing to overwrite it"
check "overmesh: the mesh is untouched" cmp -s "$T/quad.obj" "$T/quad.keep"
mkdir -p "$T/adir"
sim dirobj "$CONFIG" --steps 1 --csv "$T/dirobj.csv" --obj "$T/adir"
expect_rc dirobj 2
expect_err dirobj "exists and is a directory"
expect_err dirobj "wrote $T/dirobj.csv; $T/adir was NOT written"
check "dirobj: the directory is still there" test -d "$T/adir"
sim emptypath "$CONFIG" --steps 1 --csv "" --obj "$T/emptypath.obj"
expect_rc emptypath 2
expect_err emptypath "output path is empty"

# ---- endless or non-text input (issue 14, item 2): exit 1 at once, with a message ----------
# (timeout: the old simulate hung on /dev/zero; outputs always go to $T, never to a device)

for dev in /dev/zero /dev/urandom; do
  name=dev$(basename "$dev")
  timeout 20 "$SIM" "$dev" --csv "$T/$name.csv" --obj "$T/$name.obj" >"$T/$name.out" 2>"$T/$name.err"
  rc=$?
  expect_rc "$name" 1
  expect_err "$name" "not a regular file"
done
mkdir -p "$T/adir"
sim dir_config "$T/adir" --csv "$T/dir.csv" --obj "$T/dir.obj"
expect_rc dir_config 1
expect_err dir_config "a directory"
head -c 100 /dev/zero >"$T/nul.ini"
sim nul_config "$T/nul.ini" --csv "$T/nul.csv" --obj "$T/nul.obj"
expect_rc nul_config 1
expect_err nul_config "nul.ini:1: NUL byte"
printf '[mesh]\ntype = obj\nfile = /dev/zero\n' >"$T/devzero_mesh.ini"
timeout 20 "$SIM" "$T/devzero_mesh.ini" --csv "$T/dzm.csv" --obj "$T/dzm.obj" >/dev/null 2>"$T/devzero_mesh.err"
rc=$?
expect_rc devzero_mesh 1
expect_err devzero_mesh "devzero_mesh.ini:3: mesh.file: /dev/zero: not a regular file"

# ---- long lines, did you mean (item 7) --------------------------------------------------

pins=$(awk 'BEGIN { for (j = 0; j < 21; j++) printf "%d %d ", 21 * j, 21 * j + 20 }') # the left and right edges
three=$(awk 'BEGIN { for (j = 0; j < 21; j++) printf "%d %d %d ", 21 * j, 21 * j + 1, 21 * j + 20 }')
printf '[scene]\npins = %s\n' "$three" >"$T/long.ini" # 253 characters: over inih's 198
sim long_line "$T/long.ini" --steps 1 --quiet --csv "$T/long.csv" --obj "$T/long.obj"
expect_rc long_line 0
check "long_line: no scene line with 63 pins" grep -q '^# scene:.* 63 pinned' "$T/long.csv"
printf '[material]\nstrech_k = 1\n' >"$T/typo.ini"
sim typo "$T/typo.ini" --csv "$T/typo.csv" --obj "$T/typo.obj"
expect_rc typo 1
expect_err typo "typo.ini:2: material.strech_k: unknown key; did you mean material.stretch_k?"
printf '[mesh]\nn = 2\n[scene]\npins = corners\n[solver]\nmethod = chebyshev\n' >"$T/allpinned.ini"
sim allpinned "$T/allpinned.ini" --csv "$T/ap.csv" --obj "$T/ap.obj"
expect_rc allpinned 1
expect_err allpinned "allpinned.ini:4: scene.pins: every vertex is pinned"

# ---- finite scenes (item 1): a mesh too large for double precision is refused ---------------

printf 'v 0 0 0\nv 1e150 0 0\nv 0 1e150 0\nf 1 2 3\n' >"$T/huge.obj"
printf '[mesh]\ntype = obj\nfile = huge.obj\n[scene]\npins = 0\n[integrator]\nmethod = explicit\n' >"$T/huge.ini"
sim huge "$T/huge.ini" --steps 2 --csv "$T/huge.csv" --obj "$T/huge_out.obj"
expect_rc huge 1
expect_err huge "scene.gravity: the gravity energy at the initial state is inf J"
check "huge: a CSV with NaN rows was written" test ! -e "$T/huge.csv"
printf 'v 0 0 0\nv 1e-150 0 0\nv 0 1e-150 0\nf 1 2 3\n' >"$T/tiny.obj"
sed 's/huge.obj/tiny.obj/' "$T/huge.ini" >"$T/tiny.ini"
sim tiny "$T/tiny.ini" --steps 0 --quiet --csv "$T/tiny.csv" --obj "$T/tiny_out.obj"
expect_rc tiny 0
check "tiny: a 1e-150 mesh is not degenerate" test -s "$T/tiny.csv"

# ---- divergence (item 6): the integrator's status wins; driven pins' work counts --------------

sim driven "$CONFIG" --set "scene.pins=$pins" --set 'scene.pin_squeeze=20 0 0' --steps 30 --quiet \
  --csv "$T/driven.csv" --obj "$T/driven.obj"
expect_rc driven 0
if [ -s "$T/driven.csv" ]; then
  wc_=$(col "$T/driven.csv" pin_work_j)
  work=$(data_rows "$T/driven.csv" | tail -n 1 | cut -d, -f"$wc_")
  check "driven: pin_work_j at the end is $work, expected > 1e5 J" awk -v w="$work" 'BEGIN { exit !(w > 1e5) }'
fi
sim expl_div "$CONFIG" --set integrator.method=explicit --set integrator.dt=0.01 --steps 60 \
  --csv "$T/ed.csv" --obj "$T/ed.obj"
expect_rc expl_div 3
expect_err expl_div "energy bound"
expect_err expl_div "predicted explicit limit at the initial state is dt_crit = 2/omega_max ="

# ---- a signal leaves no temporary file behind, and the destination untouched ---------

for sig in INT TERM HUP; do
  mkdir -p "$T/sig$sig"
  echo "previous" > "$T/sig$sig/out.csv"
  # sh starts background jobs with SIGINT ignored, and nohup (or a CI runner)
  # may have SIGHUP ignored; the program keeps an ignored signal ignored, as it
  # should. perl (Essential in Debian) restores the three default actions
  # before exec, as a terminal would start it.
  perl -e '$SIG{INT} = $SIG{TERM} = $SIG{HUP} = "DEFAULT"; exec @ARGV or die' -- \
    "$SIM" "$CONFIG" --steps 100000 --quiet --csv "$T/sig$sig/out.csv" --obj "$T/sig$sig/out.obj" >/dev/null 2>&1 &
  pid=$!
  for _ in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
    ls "$T/sig$sig"/out.csv.tmp.* >/dev/null 2>&1 && break
    sleep 0.1
  done
  kill -s "$sig" "$pid" 2>/dev/null
  for _ in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$pid" 2>/dev/null; then fail "SIG$sig: simulate did not stop"; kill -9 "$pid"; fi
  wait "$pid" 2>/dev/null
  check "SIG$sig: the temporary file is removed" test -z "$(ls "$T/sig$sig" | grep tmp)"
  check "SIG$sig: the previous output is untouched" test "$(cat "$T/sig$sig/out.csv")" = previous
done

# ---- --frames DIR --every N: an OBJ sequence, step 0 first ------------------------------

sim frames "$CONFIG" --steps 7 --every 3 --frames "$T/frames" --csv "$T/frames.csv" --obj "$T/frames.obj"
expect_rc frames 0
check "frames: steps 0, 3 and 6 written" test "$(ls "$T/frames" | tr '\n' ' ')" = "frame_000000.obj frame_000003.obj frame_000006.obj "
check "frames: the last frame is the state of step 6, not the final one" test -n "$(cmp "$T/frames/frame_000006.obj" "$T/frames.obj" 2>&1)"
check "frames: a frame is a whole mesh" test "$(grep -c '^v ' "$T/frames/frame_000003.obj")" -eq 441
# an obstacle mesh (collider.type = mesh) is written beside the cloth: per frame and beside --obj
sim obst "$ROOT/configs/cylinder_turning.ini" --steps 3 --every 3 --frames "$T/obst" --csv "$T/obst.csv" --obj "$T/obst.obj"
expect_rc obst 0
check "obstacle: frames and obstacle frames of steps 0 and 3" test "$(ls "$T/obst" | tr '\n' ' ')" = "frame_000000.obj frame_000003.obj obstacle_000000.obj obstacle_000003.obj "
check "obstacle: the final obstacle beside --obj" test "$(grep -c '^f ' "$T/obst.obstacle.obj")" -eq 96
check "obstacle: it turned between steps 0 and 3" test -n "$(cmp "$T/obst/obstacle_000000.obj" "$T/obst/obstacle_000003.obj" 2>&1)"
check "obstacle: the last obstacle frame is the final obstacle" cmp -s "$T/obst/obstacle_000003.obj" "$T/obst.obstacle.obj"
mkdir -p "$T/oc" && cp "$ROOT/configs/cylinder_turning.ini" "$ROOT/configs/cylinder.obj" "$T/oc/"
sim obst_over "$T/oc/cylinder_turning.ini" --steps 1 --csv "$T/obst2.csv" --obj "$T/oc/cylinder.obj"
expect_rc obst_over 1
expect_err obst_over "is the obstacle's file (collider.file)"
sim obst_missing "$CONFIG" --steps 1 --set collider.type=mesh --set collider.file=nowhere.obj --csv "$T/om.csv" --obj "$T/om.obj"
expect_rc obst_missing 1
expect_err obst_missing "collider.file: "
for bad in 0 -2 x ""; do
  sim frames_bad "$CONFIG" --steps 2 --every "$bad" --frames "$T/frames_bad"
  expect_rc frames_bad 1
  expect_err frames_bad "--every '$bad'"
done

# ---- the OpenBLAS kernel: build/blas-kernel in front (as make runs programs) --------------
# The fallback is injected (CB_BLAS_TEST_CORENAME=Prescott, AVX-512 flags), so
# this runs the fallback path on a machine whose CPU OpenBLAS detects.

# The chosen kernel really runs (and its self-test with it), so these need a
# CPU with AVX-512 F/BW/VL/DQ.
BK=$(dirname "$SIM")/blas-kernel
AVX512="avx avx2 fma avx512f avx512bw avx512vl avx512dq"
cpu_has() { for fl in "$@"; do grep -m1 '^flags' /proc/cpuinfo | tr ' ' '\n' | grep -qx "$fl" || return 1; done; }
if [ ! -x "$BK" ]; then
  fail "blas-kernel: $BK not built"
elif ! cpu_has avx2 fma avx512f avx512bw avx512vl avx512dq; then
  echo "cli: blas-kernel checks skipped: this CPU lacks AVX-512 F/BW/VL/DQ (the chosen kernel must run here)"
else
  bk() { # NAME ENV... : blas-kernel (cache in $T) in front of simulate, env as given
    name=$1
    shift
    env -u OPENBLAS_CORETYPE -u CB_BLAS_CHOICE "$@" "$BK" --cache "$T/bk.cache" "$SIM" "$CONFIG" --steps 2 --quiet \
      --csv "$T/$name.csv" >"$T/$name.out" 2>"$T/$name.err"
    rc=$?
  }
  bk bk_chosen CB_BLAS_TEST_CORENAME=Prescott CB_BLAS_TEST_CPUFLAGS="$AVX512"
  expect_rc bk_chosen 0
  check "blas-kernel: a Prescott fallback on AVX-512 runs SkylakeX" grep -qx '# blas_kernel: SkylakeX' "$T/bk_chosen.csv"
  check "blas-kernel: the provenance says chosen, with the self-test" \
    grep -q '^# blas_kernel_choice: chosen SkylakeX; .*self-test passed: dgemm, dsyrk, dtrsm, dpotrf' "$T/bk_chosen.csv"
  check "blas-kernel: the self-test's verdict is cached" grep -q "| SkylakeX	passed" "$T/bk.cache"
  check "blas-kernel: no warning when make's wrapper chose" test ! -s "$T/bk_chosen.err"
  bk bk_env OPENBLAS_CORETYPE=Prescott CB_BLAS_TEST_CORENAME=Prescott CB_BLAS_TEST_CPUFLAGS="$AVX512"
  check "blas-kernel: a set OPENBLAS_CORETYPE is left alone" grep -qx '# blas_kernel: Prescott' "$T/bk_env.csv"
  check "blas-kernel: ... and recorded as the environment's" \
    grep -qx '# blas_kernel_choice: set by the environment (OPENBLAS_CORETYPE=Prescott)' "$T/bk_env.csv"
  bk bk_haswell CB_BLAS_TEST_CORENAME=Prescott CB_BLAS_TEST_CPUFLAGS="avx avx2 fma"
  check "blas-kernel: AVX2+FMA without AVX-512 gets Haswell" grep -qx '# blas_kernel: Haswell' "$T/bk_haswell.csv"
  # a failed self-test (its verdict put in the cache) is a refusal, with the reason
  sed 's/	passed.*/	failed: dtrsm left: 3e-09 > 1e-12 (put there by tests\/cli.sh)/' "$T/bk.cache" >"$T/bk.cache.new" &&
    mv "$T/bk.cache.new" "$T/bk.cache"
  bk bk_refused CB_BLAS_TEST_CORENAME=Prescott CB_BLAS_TEST_CPUFLAGS="$AVX512"
  expect_rc bk_refused 0
  check "blas-kernel: a failed self-test keeps the detected kernel" grep -qx '# blas_kernel: Prescott' "$T/bk_refused.csv"
  check "blas-kernel: ... and records the refusal with its reason" \
    grep -q '^# blas_kernel_choice: detected (CB_BLAS_TEST_CORENAME); .*; refused SkylakeX; .*self-test failed: dtrsm left' "$T/bk_refused.csv"
  # run directly on the (injected) fallback: one line of warning with the setting
  env -u OPENBLAS_CORETYPE -u CB_BLAS_CHOICE CB_BLAS_TEST_CORENAME=Prescott CB_BLAS_TEST_CPUFLAGS="$AVX512" \
    "$SIM" "$CONFIG" --steps 2 --quiet --csv "$T/bk_direct.csv" >"$T/bk_direct.out" 2>"$T/bk_direct.err"
  rc=$?
  expect_rc bk_direct 0
  expect_err bk_direct "simulate: warning: OpenBLAS runs its fallback Prescott kernels on this CPU, which supports SkylakeX: set OPENBLAS_CORETYPE=SkylakeX"
  check "blas-kernel: the warning is one line" test "$(grep -c 'OPENBLAS_CORETYPE' "$T/bk_direct.err")" -eq 1
  check "blas-kernel: the direct run's provenance names the setting" \
    grep -q '^# blas_kernel_choice: detected (CB_BLAS_TEST_CORENAME); .*OPENBLAS_CORETYPE=SkylakeX would select it' "$T/bk_direct.csv"
  # the self-test refuses a core OpenBLAS does not run
  OPENBLAS_CORETYPE=NoSuchCore "$BK" --self-test >"$T/bk_bogus.out" 2>&1
  rc=$?
  check "blas-kernel: the self-test of a core OpenBLAS ignores fails" test "$rc" -eq 1
  check "blas-kernel: ... saying so" grep -q '^failed: OpenBLAS runs .*, not the requested NoSuchCore' "$T/bk_bogus.out"
  "$BK" --cache "$T/bk.cache" >/dev/null 2>&1
  rc=$?
  check "blas-kernel: no program is a usage error" test "$rc" -eq 2
fi

# ---- issue 21, defects 6 and 19: a duplicated face, extreme OBJ scales: the message names the real problem ----

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 1 3 2\n' >"$T/dupface.obj"
for bend in none quadratic spring; do
  printf '[mesh]\ntype = obj\nfile = dupface.obj\n[material]\nbend = %s\n[scene]\npins = 0\n' "$bend" >"$T/dupface.ini"
  sim "dupface_$bend" "$T/dupface.ini" --steps 1 --csv "$T/dupface.csv" --obj "$T/dupface_out.obj"
  expect_rc "dupface_$bend" 1
  expect_err "dupface_$bend" "dupface.obj:7: face duplicates line 5"
done
for case in "tiny 1e-300 too small" "huge 1e300 too large" "inf 1e308 too large"; do
  set -- $case
  if [ "$1" = inf ]; then printf 'v -%s 0 0\nv %s 0 0\nv 0 1 0\nf 1 2 3\n' "$2" "$2"; else printf 'v 0 0 0\nv %s 0 0\nv 0 %s 0\nf 1 2 3\n' "$2" "$2"; fi >"$T/obj_$1.obj"
  printf '[mesh]\ntype = obj\nfile = obj_%s.obj\n[scene]\npins = 0\n' "$1" >"$T/obj_$1.ini"
  sim "obj_$1" "$T/obj_$1.ini" --steps 1 --csv "$T/obj_$1.csv" --obj "$T/obj_$1_out.obj"
  expect_rc "obj_$1" 1
  expect_err "obj_$1" "coordinates are $3"
done
check "obj_tiny: 'belongs to no triangle' for a valid triangle" test -z "$(grep 'belongs to no triangle' "$T/obj_tiny.err")"
check "obj_inf: called zero area" test -z "$(grep 'zero area' "$T/obj_inf.err")"

# ---- issue 21, defects 14 and 15: a dt or a scale below double precision's reach is refused, with the cause ----

sim tiny_dt "$CONFIG" --steps 2 --set integrator.dt=1e-160 --csv "$T/tiny_dt.csv" --obj "$T/tiny_dt.obj"
expect_rc tiny_dt 1
expect_err tiny_dt "integrator.dt = 1e-160 s is too small for double precision: the inertia term M/dt^2"
check "tiny_dt: a CSV was written" test ! -e "$T/tiny_dt.csv"
for m in explicit newton; do
  sim "tiny_scale_$m" "$CONFIG" --steps 2 --set scene.initial_scale=1e-200 --set integrator.method=$m --csv "$T/ts.csv" --obj "$T/ts.obj"
  expect_rc "tiny_scale_$m" 1
  expect_err "tiny_scale_$m" "scene.initial_scale = 1e-200: the edge between vertices 0 and 1 has zero length at the initial state"
done
check "tiny_scale: an OBJ of NaN vertices was written" test ! -e "$T/ts.obj"

# ---- issue 21, defects 1, 2, 12, 13: --frames is a folder, checked, never mixed or cut ------

for bad in "" -; do # defect 1: '' wrote into /, - made a folder named -
  (cd "$T" && "$SIM" "$CONFIG" --steps 1 --frames "$bad" --csv "$T/fr_bad.csv" --obj "$T/fr_bad.obj" >/dev/null 2>"$T/fr_bad.err")
  rc=$?
  expect_rc fr_bad 1
  expect_err fr_bad "--frames '$bad': expected a folder name"
  check "frames '$bad': a CSV was written" test ! -e "$T/fr_bad.csv"
done
check "frames -: a folder named - was made" test ! -e "$T/-"
sim every_alone "$CONFIG" --steps 1 --every 2 --csv "$T/ea.csv" --obj "$T/ea.obj"
expect_rc every_alone 1
expect_err every_alone "give --frames too"
# defect 2: the mesh file, --obj and --csv may not be frames
mkdir -p "$T/frin"
cp "$T/quad.obj" "$T/frin/frame_000000.obj"
printf '[mesh]\ntype = obj\nfile = frin/frame_000000.obj\n[material]\nvertex_mass = 1\n[scene]\npins = 0\n' >"$T/frin.ini"
sim fr_mesh "$T/frin.ini" --steps 1 --frames "$T/frin" --csv "$T/frin.csv" --obj "$T/frin.obj"
expect_rc fr_mesh 1
expect_err fr_mesh "would overwrite the mesh file (mesh.file)"
check "fr_mesh: the input mesh was overwritten" cmp -s "$T/frin/frame_000000.obj" "$T/quad.obj"
sim fr_obj "$CONFIG" --steps 2 --frames "$T/frout" --csv "$T/frout.csv" --obj "$T/frout/frame_000000.obj"
expect_rc fr_obj 1
expect_err fr_obj "--obj $T/frout/frame_000000.obj is a frame of --frames"
sim fr_csv "$CONFIG" --steps 2 --frames "$T/./frout" --csv "$T/frout/frame_000001.obj" --obj "$T/frout.obj"
expect_rc fr_csv 1
expect_err fr_csv "is a frame of --frames"
# defect 13: a 2-step run into a folder with a 10-step run's frames keeps none of them
sim fr_ten "$CONFIG" --steps 10 --quiet --frames "$T/frold" --csv "$T/frold.csv" --obj "$T/frold.obj"
echo keep >"$T/frold/notes.txt"
sim fr_two "$CONFIG" --steps 2 --frames "$T/frold" --csv "$T/frold.csv" --obj "$T/frold.obj"
expect_rc fr_two 0
expect_err fr_two "removed 11 frames of an earlier run from $T/frold/ (frame_000000.obj to frame_000010.obj)"
check "fr_two: frames 0-2 and notes.txt, nothing else" test "$(ls "$T/frold" | tr '\n' ' ')" = "frame_000000.obj frame_000001.obj frame_000002.obj notes.txt "
# defect 12: a frame that cannot be written stops the run and nothing is committed
mkdir -p "$T/frcut/frame_000003.obj"
echo previous >"$T/frcut.csv"
sim fr_cut "$CONFIG" --steps 10 --frames "$T/frcut" --csv "$T/frcut.csv" --obj "$T/frcut.obj"
expect_rc fr_cut 2
expect_err fr_cut "frame_000003.obj is not a regular file" # refused before the run (issue 35 item 6: frames are staged)
expect_err fr_cut "NOTHING written"
check "fr_cut: the previous CSV was replaced by a cut one" test "$(cat "$T/frcut.csv")" = previous
check "fr_cut: an OBJ was written" test ! -e "$T/frcut.obj"
check "fr_cut: this run's frames were kept" test "$(ls "$T/frcut")" = frame_000003.obj
sim version --version
expect_rc version 0
check "simulate --version: no 'simulate (clothbench) <revision>' line" grep -q '^simulate (clothbench) ' "$T/version.out"

# ---- issue 21, defect 3: tiny stiffnesses the range check accepts finish ------------------
# (timeout: GSL's symmetric eigensolver looped for ever on subnormal element Hessians)

printf '[mesh]\nn = 6\nsize = 1\n[integrator]\nsteps = 3\n' >"$T/grid6.ini"
i=0
for sets in "material.stretch=fem material.stretch_k=1e-300" "material.bend=dihedral material.bend_k=1e-300" \
  "integrator.method=explicit material.stretch_k=1e-300 collider.type=project"; do
  i=$((i + 1))
  args=
  for s_ in $sets; do args="$args --set $s_"; done
  # shellcheck disable=SC2086
  timeout 60 "$SIM" "$T/grid6.ini" $args --quiet --csv "$T/tinyk$i.csv" --obj "$T/tinyk$i.obj" >/dev/null 2>"$T/tinyk$i.err"
  rc=$?
  check "tinyk$i ($sets): timed out or crashed (exit $rc)" test "$rc" -ne 124 -a "$rc" -lt 5
  check "tinyk$i ($sets): no CSV" test -s "$T/tinyk$i.csv"
done

# ---- issue 21, smaller points: halfspace at 1e-300, an index past long, the rho = auto estimate ----

sim hs_tiny "$CONFIG" --steps 0 --quiet --set "scene.pins=halfspace 1e-300 0 0 0" --csv "$T/hs.csv" --obj "$T/hs.obj"
expect_rc hs_tiny 0
check "hs_tiny: halfspace 1e-300 0 0 0 does not pin the x <= 0 half (231 vertices)" grep -q '^# scene:.* 231 pinned' "$T/hs.csv"
sim pins_huge "$CONFIG" --steps 0 --set "scene.pins=99999999999999999999" --csv "$T/ph.csv" --obj "$T/ph.obj"
expect_rc pins_huge 1
expect_err pins_huge "vertex 99999999999999999999 out of range"
sim rho_auto "$CONFIG" --steps 2 --quiet --set integrator.method=chebyshev-nl --set integrator.rho=auto --csv "$T/rho.csv" --obj "$T/rho.obj"
expect_rc rho_auto 0
if [ -s "$T/rho.csv" ]; then
  rc_=$(col "$T/rho.csv" rho)
  rho=$(data_rows "$T/rho.csv" | tail -n 1 | cut -d, -f"${rc_:-1}")
  check "rho_auto: the estimate is not in the CSV's rho column (got '$rho')" awk -v r="$rho" 'BEGIN { exit !(r > 0 && r < 1) }'
fi

# ---- issue 21, defect 20: pd's refusal names the key that fixes it -------------------------

for case in "material.stretch=fem|set material.stretch = spring" "collider.type=penalty|set collider.type = project" \
  "material.bend=dihedral|set material.bend = none" "integrator.definiteness=choi-ko|set integrator.definiteness to none"; do
  sim pd_refuse "$CONFIG" --steps 1 --set integrator.method=pd --set "${case%%|*}" --csv "$T/pdr.csv" --obj "$T/pdr.obj"
  expect_rc pd_refuse 1
  expect_err pd_refuse "${case#*|}"
done

# ---- issue 21, defects 16, 18 and the --shard point: the experiments' shared options (lib/io/experiment.c) ----

EXP_DIR=$(dirname "$SIM")
if [ -x "$EXP_DIR/topology" ] && [ -x "$EXP_DIR/bending" ]; then
  long=$(awk 'BEGIN { for (i = 0; i < 2100; i++) printf "x" }')
  CB_QUIET=1 "$EXP_DIR/topology" --smoke --out "$T/$long.csv" >/dev/null 2>"$T/longout.err"
  rc=$?
  expect_rc longout 1
  expect_err longout "at most 1983 are allowed"
  check "longout: a cut --out path was written" test -z "$(ls "$T" | grep '^xxxxxxxxxx')"
  CB_QUIET=1 "$EXP_DIR/bending" --smoke --shard 1/2 --out "$T/bshard.csv" >/dev/null 2>"$T/bshard.err"
  rc=$?
  expect_rc bshard 1
  expect_err bshard "cannot be sharded"
  check "bshard: a CSV was written" test ! -e "$T/bshard.csv"
  mkdir -p "$T/cfg300"
  cp "$ROOT"/configs/*.ini "$ROOT"/configs/*.obj "$T/cfg300/"
  i=0
  while [ $i -lt 300 ]; do printf '[mesh]\nn = 3\n' >"$T/cfg300/extra$i.ini"; i=$((i + 1)); done
  CB_QUIET=1 "$EXP_DIR/topology" --smoke --configs "$T/cfg300" --out "$T/cfg300.csv" >/dev/null 2>"$T/cfg300.err"
  rc=$?
  expect_rc cfg300 0
  want=$(ls "$T/cfg300" | grep -c '\.ini$')
  check "cfg300: the provenance lists $(grep -c '^# config ' "$T/cfg300.csv") of the $want configs" \
    test "$(grep -c '^# config ' "$T/cfg300.csv")" -eq "$want"
else
  echo "cli: notice: $EXP_DIR/topology or bending not built; the experiments' option checks skipped"
fi

if [ "$failures" -ne 0 ]; then
  echo "cli: $failures of $checks checks failed"
  exit 1
fi
echo "cli: ok ($checks checks)"
exit 0
