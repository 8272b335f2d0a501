#!/bin/sh
# End-to-end checks of build/simulate as a user runs it.
set -u
B=${BUILD:-build}
echo "cli: ok (placeholder)"
