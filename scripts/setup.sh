#!/usr/bin/env bash
# Install the Debian packages fesph needs (only the missing ones), configure CMake in Release
# and build. Idempotent: a second call only rebuilds what changed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FESPH_BUILD_DIR:-$root/build}

packages=(cmake g++ make pkg-config libeigen3-dev libvtk9-dev libosmesa6-dev libhdf5-dev
          hdf5-tools catch2 libgmsh-dev libtomlplusplus-dev libcli11-dev libbenchmark-dev
          libreadline-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

mkdir -p "$build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release > "$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)"
