#!/usr/bin/env bash
# Installs the Debian packages shadowlab needs (DESIGN.md section 10). Does nothing when all are
# present; uses sudo when not root.
set -euo pipefail
PKGS=(
  build-essential cmake pkg-config
  libglfw3-dev libglm-dev libvtk9-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev
  libtinygltf-dev nlohmann-json3-dev libstb-dev libimgui-dev
  libembree-dev libgtest-dev googletest
  xvfb xauth ccache
)
missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "shadowlab: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
