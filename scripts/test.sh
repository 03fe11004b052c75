#!/usr/bin/env bash
# The test command: set up (packages, build), then run every test not labelled `slow`.
# Run the slow verification scenes on their own with: ctest --test-dir build -L slow
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
build=${FESPH_BUILD_DIR:-$root/build}
cd "$build"
ctest -LE slow --output-on-failure -j "$(nproc)" "$@"
