#!/usr/bin/env bash
# Runs every libFuzzer target of the build for SECONDS in all (default 60, split evenly among them):
#   model_fuzzer   model parsing, validation and CPU evaluation (tests/fuzz/model_fuzzer.cpp)
#   merge_fuzzer   shard files of every format through jobs::mergeShards (tests/fuzz/merge_fuzzer.cpp)
#   and any other NAME_fuzzer target the build defines (e.g. eval_at_fuzzer, `eval --at` files).
# Builds with clang into ./build-fuzz (ASan + UBSan + libFuzzer). Each fuzzer NAME_fuzzer gets its
# own folder build-fuzz/fuzz/NAME/: seeds/ (written by the NAME_fuzz_seeds target when there is one,
# else build-fuzz/fuzz/NAME_seeds/ is used when present), corpus/ (the inputs it finds), artifacts/
# and fuzz.log; tests/fuzz/NAME.dict is its dictionary when present. Any crash, sanitizer report,
# leak or input slower than 5 s fails, and the input is saved under the fuzzer's artifacts/ (replay:
# build-fuzz/tests/fuzz/NAME_fuzzer FILE). Every fuzzer runs even when an earlier one failed.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
root=$PWD

CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSHAPESPLINE_FUZZ=ON -DSHAPESPLINE_BUILD_BENCH=OFF >/dev/null

# The fuzz targets and seed writers this tree defines (tolerant of targets added or not yet there).
# (Ninja also lists CMake's own cmake_object_order_depends_target_* phonies: skipped.)
phonies=$(ninja -C build-fuzz -t targets all | sed -n 's/^\([A-Za-z0-9_]*\): phony$/\1/p' | grep -v '^cmake_' | sort -u)
targets=$(sed -n 's/^\([A-Za-z0-9_]*\)_fuzzer$/\1/p' <<<"$phonies")
if [[ -z $targets ]]; then
  echo "fuzz: no *_fuzzer target in build-fuzz" >&2
  exit 1
fi
seeders=$(grep '_fuzz_seeds$' <<<"$phonies" || true)
build=()
for name in $targets; do build+=("${name}_fuzzer"); done
for s in $seeders; do build+=("$s"); done
cmake --build build-fuzz -j "$(nproc)" --target "${build[@]}"
echo "stage: fuzz build $SECONDS s" >&2

count=$(wc -w <<<"$targets")
per=$((seconds / count))
((per >= 1)) || per=1
echo "fuzz: $count fuzzers ($(echo $targets)), ${per} s each"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
failed=()
for name in $targets; do
  out=build-fuzz/fuzz/$name
  mkdir -p "$out/corpus" "$out/artifacts"
  folders=("$out/corpus")
  seeder=$(find build-fuzz/tests -name "${name}_fuzz_seeds" -type f -perm -u+x | head -n 1)
  if [[ -n $seeder ]]; then
    rm -rf "$out/seeds"
    "$seeder" "$out/seeds"
    folders+=("$out/seeds")
  elif [[ -d build-fuzz/fuzz/${name}_seeds ]]; then
    folders+=("build-fuzz/fuzz/${name}_seeds")
  fi
  options=(-max_total_time="$per" -timeout=5 -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$out/artifacts/"
    -print_final_stats=1)
  [[ -f $root/tests/fuzz/$name.dict ]] && options+=(-dict="$root/tests/fuzz/$name.dict")
  # New inputs go to the first folder; the seeds are read only. libFuzzer's progress lines
  # (thousands) go to the log; the summary is printed, and on failure the log's tail with the report.
  log="$out/fuzz.log"
  binary=$(find build-fuzz/tests -name "${name}_fuzzer" -type f -perm -u+x | head -n 1)
  if [[ -n $binary ]] && "$binary" "${options[@]}" "${folders[@]}" >"$log" 2>&1; then
    grep -E '^(Done|stat::)' "$log" || true
    echo "fuzz: ${name}_fuzzer: no crash, leak, sanitizer report or timeout in ${per} s (log: $log)"
  else
    status=$?
    [[ -f $log ]] && tail -n 200 "$log"
    echo "fuzz: ${name}_fuzzer FAILED (exit $status); inputs in $out/artifacts/" >&2
    failed+=("${name}_fuzzer")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz: FAILED: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: all $count fuzzers clean in ${seconds} s"
