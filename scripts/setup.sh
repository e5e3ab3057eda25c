#!/usr/bin/env bash
# Installs every build and test dependency from Debian 12 packages, and the Khronos glTF validator
# (npm package gltf-validator, pinned in tests/tools/gltf/package-lock.json) with `npm ci` from the
# npm registry. Idempotent: a machine that already has them installs nothing. Runs as root, or
# through sudo when available (npm ci runs as the calling user: it writes only into the tree).
# `setup.sh --demo` installs only what building the shapespline command and running its demo need
# (scripts/demo.sh): no test tools, sanitizer runtimes, cluster, Python, Open CASCADE or Node.js.
set -euo pipefail

DEMO_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libvulkan-dev mesa-vulkan-drivers glslang-tools
  libglm-dev nlohmann-json3-dev libcli11-dev libpng-dev libssl-dev libimgui-dev libtinygltf-dev libglfw3-dev
)
PACKAGES=(
  cmake ninja-build g++ clang libclang-rt-14-dev pkg-config dpkg-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglm-dev nlohmann-json3-dev libcli11-dev libpng-dev libssl-dev libimgui-dev
  libgtest-dev libgmock-dev libbenchmark-dev libosd-dev
  python3-numpy libtinygltf-dev assimp-utils python3-open3d
  slurm-wlm munge
  libglfw3-dev xvfb xauth
  pybind11-dev python3-dev python3-pytest python3-matplotlib python3-scipy
  # Open CASCADE for `shapespline import` (host/cad/); its CMake targets link TBB's .so files.
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libtbb-dev
)

demo=0
if [[ ${1:-} == --demo ]]; then
  demo=1
  PACKAGES=("${DEMO_PACKAGES[@]}")
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js for the glTF validator: Debian's nodejs and npm, unless a Node.js is installed already
# (a nodesource nodejs package carries its own npm and must not be replaced by Debian's).
if ((demo)); then
  :
elif ! dpkg-query -W -f='${Status}' nodejs 2>/dev/null | grep -q "install ok installed"; then
  missing+=(nodejs npm)
elif ! command -v npm >/dev/null 2>&1 &&
    ! dpkg-query -W -f='${Status}' npm 2>/dev/null | grep -q "install ok installed"; then
  missing+=(npm)
fi

if ((${#missing[@]} > 0)); then
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  echo "setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ((demo)); then exit 0; fi

# The glTF validator, exactly the version of the lock file (tests/cli/gltf_output_test.cpp runs
# tests/tools/gltf/validate.js). Skipped when node_modules already holds that version.
gltf_tools="$(cd "$(dirname "$0")/.." && pwd)/tests/tools/gltf"
want=$(sed -n 's/.*"gltf-validator": *"\([^"]*\)".*/\1/p' "$gltf_tools/package.json")
have=$(node -p "require('$gltf_tools/node_modules/gltf-validator/package.json').version" 2>/dev/null || true)
if [[ "$have" != "$want" ]]; then
  echo "setup: installing gltf-validator $want (npm ci in tests/tools/gltf)" >&2
  (cd "$gltf_tools" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error >/dev/null)
fi
