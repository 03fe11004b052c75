#!/usr/bin/env bash
# The main job: set up (packages, build), then run the default scene end to end.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
build=${FESPH_BUILD_DIR:-$root/build}
scene=${1:-$root/scenes/single_plate/scene.toml}
out=${2:-$root/runs/main}
"$build/fesph" run "$scene" --out "$out"
