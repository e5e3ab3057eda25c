#!/usr/bin/env bash
# Quick start #1: set up, build, and run the main job on the built-in default models
# (`shapespline demo` writes example models, OBJ meshes and SVG plots into ./shapespline-demo/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/host/cli/shapespline demo "$@"
