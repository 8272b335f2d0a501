#!/bin/sh
# make report: runs the claims checker (make builds it first: build/report).
set -eu
B=${BUILD:-build}
[ -x "$B/report" ] || { echo "report: $B/report not built (run: make report)" >&2; exit 1; }
"$B/report" "$@"
