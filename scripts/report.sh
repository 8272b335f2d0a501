#!/bin/sh
# make report: builds and runs the claims checker (report/).
set -eu
${MAKE:-make} --no-print-directory build/report
build/report "$@"
