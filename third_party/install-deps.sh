#!/usr/bin/env bash
# Installs Lava's build and test dependencies from Debian packages, only those missing, and
# fetches lavapipe 25 and SwiftShader into a private folder for the tests (fetch-drivers.sh).
# Safe to run again; uses sudo when not root. Nothing is downloaded except by apt.
set -euo pipefail

packages=(
  build-essential clang libfuzzer-14-dev cmake pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglfw3-dev libx11-dev libxext-dev libglm-dev libgtest-dev
  libcli11-dev libtomlplusplus-dev libstb-dev libimgui-dev libhwy-dev
  python3 python3-dev pybind11-dev python3-numpy python3-pytest
  python3-vtk9 python3-matplotlib python3-venv python3-pip python3-setuptools python3-wheel python3-build
  xvfb xauth xdotool x11-apps x11-utils twm procps
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "third_party: installing ${missing[*]}"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The other Vulkan implementations the tests run on, into a private folder (cached).
"$(dirname "$0")/fetch-drivers.sh"
