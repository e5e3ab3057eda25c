#!/usr/bin/env bash
# Quick start #2: set up, build, and run the whole test suite (CPU core, GPU on lavapipe, CLI); then
# the same suite under AddressSanitizer + UndefinedBehaviorSanitizer (scripts/sanitize.sh, build-asan)
# and 60 s of the model fuzzer (scripts/fuzz.sh, clang, build-fuzz). Locally,
# SHAPESPLINE_SKIP_SANITIZERS=1 and SHAPESPLINE_SKIP_FUZZ=1 skip those two stages.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
if [[ "${SHAPESPLINE_SKIP_SANITIZERS:-0}" != 1 ]]; then
  bash scripts/sanitize.sh
fi
if [[ "${SHAPESPLINE_SKIP_FUZZ:-0}" != 1 ]]; then
  bash scripts/fuzz.sh 60
fi
