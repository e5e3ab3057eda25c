#!/usr/bin/env bash
# Quick start #2: set up, build, and run the whole test suite (CPU core, GPU on lavapipe, CLI); then
# the same suite under AddressSanitizer + UndefinedBehaviorSanitizer (scripts/sanitize.sh, build-asan)
# and 60 s of the model fuzzer (scripts/fuzz.sh, clang, build-fuzz). Locally,
# SHAPESPLINE_SKIP_SANITIZERS=1 and SHAPESPLINE_SKIP_FUZZ=1 skip those two stages.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's wall time, printed as it ends and summed up at the end ("stage: NAME N s").
stages=()
stage() {
  local name=$1 start=$SECONDS
  shift
  "$@"
  stages+=("$name $((SECONDS - start)) s")
  echo "stage: ${stages[-1]}" >&2
}
stage setup bash scripts/setup.sh
# The test code itself at -Og (what it tests keeps Release's -O3): it compiles in half the time
# (test sources were 45% of the build's CPU time), and the sanitizer stage runs it so already.
stage build bash scripts/build.sh -DSHAPESPLINE_TEST_CXX_FLAGS=-Og
run_ctest() { ctest --test-dir build --output-on-failure -j "$(nproc)" | tee build/ctest-summary.log; }
stage ctest run_ctest
total=$(sed -n 's/.*tests failed out of \([0-9]*\).*/\1/p' build/ctest-summary.log | tail -n 1)
if [[ "${SHAPESPLINE_SKIP_SANITIZERS:-0}" != 1 ]]; then
  stage sanitizers bash scripts/sanitize.sh
fi
if [[ "${SHAPESPLINE_SKIP_FUZZ:-0}" != 1 ]]; then
  stage fuzz bash scripts/fuzz.sh 60
fi
# Reached only when every stage passed: one line for the whole suite (the sanitizer stage's own
# ctest summary above counts only its fuzz-replay tests).
echo "stages: $(IFS=,; echo "${stages[*]}" | sed 's/,/, /g'); total $SECONDS s"
echo "suite: ${total:-0} passed, 0 failed"
