#!/usr/bin/env bash
# Check that ParaView 5.11 opens a fesph series: install ParaView's Python privately (once),
# run a short scene and check times, arrays and cell types with pvpython. Run on its own:
#   bash tools/check_paraview.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build}
prefix=${FESPH_PARAVIEW_PREFIX:-/opt/fesph-paraview}
"$root/tools/install_paraview.sh" > /dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$build/fesph" run "$root/scenes/taylor_benchmark/scene.toml" --out "$out" --quiet --no-images \
  --end-time 2e-6 --set output.interval=1e-6 --set bodies.0.shape.mesh_size=1.2e-3 > /dev/null
env -u PYTHONPATH "$prefix/usr/bin/pvpython" "$root/tools/check_series.py" "$out" --expect-steps 3
