#!/usr/bin/env bash
# Quick start #2: set up, build, and run the whole test suite (CPU core, GPU on lavapipe, CLI, Python,
# package, Slurm, viewer); the gtest executables run under AddressSanitizer + UndefinedBehaviorSanitizer
# (scripts/sanitize.sh, build-asan), then 60 s of the model fuzzer (scripts/fuzz.sh, clang,
# build-fuzz). Locally, SHAPESPLINE_SKIP_SANITIZERS=1 runs every gtest in the Release build instead,
# and SHAPESPLINE_SKIP_FUZZ=1 skips the fuzzer.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/test_sets.sh
# Each stage's wall time, printed as it ends and summed up at the end ("stage: NAME N s").
stages=()
stage() {
  local name=$1 start=$SECONDS
  shift
  "$@"
  stages+=("$name $((SECONDS - start)) s")
  echo "stage: ${stages[-1]}" >&2
}
sanitize=1
[[ "${SHAPESPLINE_SKIP_SANITIZERS:-0}" == 1 ]] && sanitize=0
stage setup bash scripts/setup.sh
fuzz=1
[[ "${SHAPESPLINE_SKIP_FUZZ:-0}" == 1 ]] && fuzz=0
# The fuzzers' clang build starts now, in the background at the lowest priority, to use the CPU time
# the stages before the fuzz stage leave idle (the Release tests use 1.6 of two cores): the fuzz
# stage then finds it built (107 -> 35 s; the sanitizer run took about 70 s longer beside it, see
# docs/performance.md). Its own session, so that an exit stops all of it; a new session is also a
# new scheduler autogroup (Linux), which gets as much CPU as ours whatever its processes' nice
# values, so the autogroup itself is set to nice 19 where the kernel has them.
fuzz_build=
if ((fuzz)); then
  mkdir -p build-fuzz
  early='echo 19 >/proc/self/autogroup 2>/dev/null; exec nice -n 19 bash scripts/fuzz.sh'
  setsid env SHAPESPLINE_FUZZ_BUILD_ONLY=1 bash -c "$early" >build-fuzz/early-build.log 2>&1 &
  fuzz_build=$!
  trap '[[ -n $fuzz_build ]] && kill -- -"$fuzz_build" 2>/dev/null || true' EXIT
fi
# The test code itself at -Og (what it tests keeps Release's -O3): it compiles in half the time
# (test sources were 45% of the build's CPU time), and the sanitizer stage runs it so already.
# With the sanitizer stage, the Release build has only the tests it runs (below).
stage build bash scripts/build.sh -DSHAPESPLINE_TEST_CXX_FLAGS=-Og -DSHAPESPLINE_RELEASE_STAGE_TESTS=$((sanitize ? 1 : 0))
# Release: the tests that are not gtests (Python, package, Slurm, viewer; fuzz seeds when nothing
# else replays them) and scripts/test_sets.sh's Release gtests. Every other gtest runs once, in the
# sanitizer stage: the same code, checked more strictly. Running them here too took 7 min of a
# 25-min CI run (one process per test, 2,500 processes) to check what the sanitizer run checks too.
release_logs=build/test-logs
release_tests() {
  rm -rf "$release_logs"
  mkdir -p "$release_logs"
  local labels=(-LE gtest)
  ((sanitize)) || labels=()
  ctest --test-dir build --output-on-failure -j "$(nproc)" "${labels[@]}" | tee "$release_logs/ctest.log"
  ((sanitize)) || return 0
  local exe
  for exe in "${release_gtests[@]}"; do
    build/tests/$exe --gtest_brief=1 --gtest_output="xml:$release_logs/$exe.xml"
  done
}
stage tests release_tests
if ((sanitize)); then
  # The fuzz stage below runs every seed set under the sanitizers too: no replay of them here.
  stage sanitizers env SHAPESPLINE_REPLAY_FUZZ_SEEDS=$((fuzz ? 0 : 1)) bash scripts/sanitize.sh
fi
if ((fuzz)); then
  # The early build's outcome does not matter here: fuzz.sh builds what is missing and reports
  # a build error itself.
  wait "$fuzz_build" || true
  fuzz_build=
  stage fuzz bash scripts/fuzz.sh 60
fi
# Reached only when every stage passed: one line for the whole suite. Counts: ctest's summary, and
# the `tests` of each gtest XML report (the root element's first attribute).
gtests_in() { cat "$@" 2>/dev/null | sed -n 's/^<testsuites tests="\([0-9]*\)".*/\1/p' | awk '{n += $1} END {print n + 0}'; }
ctest_count=$(sed -n 's/.*tests failed out of \([0-9]*\).*/\1/p' "$release_logs/ctest.log" | tail -n 1)
release_count=$((${ctest_count:-0} + $(gtests_in "$release_logs"/*.xml)))
sanitized_count=$(gtests_in build-asan/sanitize-logs/*.xml)
echo "stages: $(IFS=,; echo "${stages[*]}" | sed 's/,/, /g'); total $SECONDS s"
if ((sanitize)); then
  echo "suite: $((release_count + sanitized_count)) passed, 0 failed ($release_count in Release, $sanitized_count gtests under the sanitizers)"
else
  echo "suite: $release_count passed, 0 failed"
fi
