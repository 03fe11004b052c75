#!/usr/bin/env bash
# The main job: set up (packages, build), then run the four-plate reference scene at the quick
# resolution end to end (mesh, FE-SPH run, ParaView series, images, residual velocities) and
# write its report. Another scene: scripts/main.sh SCENE.toml [OUT_DIR] (run as the file says).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
build=${FESPH_BUILD_DIR:-$root/build}
if (($# > 0)); then
  "$build/fesph" run "$1" --out "${2:-$root/runs/main}"
  exit
fi
out=$root/runs/main
"$build/fesph" run "$root/scenes/four_plates_normal/scene.toml" --set resolution='"quick"' --out "$out"
"$build/fesph" report "$out" --out "$out/report"
