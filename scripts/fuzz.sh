#!/usr/bin/env bash
# Fuzzes model parsing, validation and CPU evaluation (tests/fuzz/model_fuzzer.cpp) with libFuzzer
# for SECONDS (default 60). Builds with clang into ./build-fuzz (ASan + UBSan + libFuzzer), writes
# the seed corpus (examples, golden models, bad-input catalog) and keeps the inputs it finds in
# build-fuzz/fuzz/corpus. Any crash, sanitizer report, leak or input slower than 5 s fails, and the
# input is saved under build-fuzz/fuzz/artifacts/ (replay: build-fuzz/tests/fuzz/model_fuzzer FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
root=$PWD

CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSHAPESPLINE_FUZZ=ON -DSHAPESPLINE_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target model_fuzzer model_fuzz_seeds

out=build-fuzz/fuzz
rm -rf "$out/seeds"
mkdir -p "$out/corpus" "$out/artifacts"
build-fuzz/tests/fuzz/model_fuzz_seeds "$out/seeds"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
# New inputs go to the first folder; the seeds are read only. libFuzzer's progress lines (thousands)
# go to a log; the summary is printed, and on failure the log's tail with the report.
log="$out/fuzz.log"
if build-fuzz/tests/fuzz/model_fuzzer -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len=65536 \
  -dict="$root/tests/fuzz/model.dict" -artifact_prefix="$out/artifacts/" -print_final_stats=1 \
  "$out/corpus" "$out/seeds" >"$log" 2>&1; then
  grep -E '^(Done|stat::)' "$log" || true
  echo "fuzz: no crash, leak, sanitizer report or timeout in ${seconds} s (log: $log)"
else
  status=$?
  tail -n 200 "$log"
  echo "fuzz: FAILED (exit $status); inputs in $out/artifacts/" >&2
  exit "$status"
fi
