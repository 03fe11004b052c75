#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Private install of ParaView 5.11's Python (pvpython) next to libvtk9-dev, for tools/check_series.py.
# Idempotent. Usage: tools/install_paraview.sh [PREFIX]  (default ${FESPH_PARAVIEW_PREFIX:-/opt/fesph-paraview})
#
# python3-paraview Conflicts: python3-vtk9, which libvtk9-dev needs, so it is never apt-installed:
# it is unpacked with dpkg -x into PREFIX instead (docs: /work/shared/reference/paraview.md, section 1).
set -euo pipefail

PREFIX=${1:-${FESPH_PARAVIEW_PREFIX:-/opt/fesph-paraview}}
PVPYTHON="$PREFIX/usr/bin/pvpython"

SUDO=
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi

# The paraview package brings the shared libraries pvpython loads; xvfb/xauth are for screenshots.
PACKAGES=(paraview xvfb xauth)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update -qq
  # Refuse anything that would remove packages (libvtk9-dev, python3-vtk9, ...).
  removals=$($SUDO apt-get install -s --no-install-recommends "${missing[@]}" | grep '^Remv' || true)
  if [ -n "$removals" ]; then
    echo "install_paraview.sh: installing ${missing[*]} would remove packages, aborting:" >&2
    echo "$removals" >&2
    exit 1
  fi
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ ! -x "$PREFIX/usr/bin/pvpython3.11" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  # The sandbox option keeps apt from warning that _apt cannot write to a private directory.
  (cd "$tmp" && apt-get download -qq -o APT::Sandbox::User=root python3-paraview)
  $SUDO mkdir -p "$PREFIX"
  $SUDO dpkg -x "$tmp"/python3-paraview_*.deb "$PREFIX"
fi

# pvpython finds its vtkmodules relative to its own path; a PYTHONPATH would shadow them.
version=$(env -u PYTHONPATH "$PVPYTHON" -c \
  "from paraview.simple import GetParaViewVersion; print(GetParaViewVersion())")
echo "ParaView $version"
echo "pvpython: $PVPYTHON"
