#!/usr/bin/env bash
# Install the Debian 12 packages the build needs, when missing. Runs as root (or via sudo).
set -euo pipefail
packages=(g++ cmake make ccache clang libclang-rt-14-dev libomp-dev libeigen3-dev libcli11-dev nlohmann-json3-dev libgtest-dev libhdf5-dev libhdf5-openmpi-dev libtomlplusplus-dev libmuparser-dev python3-matplotlib python3-vtk9 openmpi-bin libopenmpi-dev pybind11-dev python3-dev python3-numpy python3-pytest clang-format-14 libassimp-dev libgmsh-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  echo "installing: ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi
