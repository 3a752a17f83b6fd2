#!/usr/bin/env bash
# CI's third step. The library, the program and the fuzz targets (fuzz/) built with
# Debian's clang++, every warning an error (the code is not GCC's alone), with libFuzzer,
# AddressSanitizer and UndefinedBehaviorSanitizer (or BUILD_DIR's build of them, as
# tests/sanitize.sh leaves build-asan); then each target run for SECONDS from its
# committed corpus, its regression inputs and the dictionary, two at a time: any crash,
# leak, timeout or out-of-memory fails (the input is kept in BUILD_DIR/fuzz-findings/).
# Usage: tests/fuzz.sh [SECONDS [BUILD_DIR]]   (default 60, build-fuzz)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
dir=${2:-build-fuzz}
# A build that has them already (tests/sanitize.sh's, as CI's) is used as it is.
if ! grep -q '^LAVA_FUZZ:BOOL=ON' "$dir/CMakeCache.txt" 2>/dev/null; then
  # Line tables only (-g1), as in tests/sanitize.sh: reports name file and line.
  CC=clang CXX=clang++ cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLAVA_FUZZ=ON \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS=-Werror -DLAVA_BUILD_TESTS=OFF -DLAVA_BUILD_PYTHON=OFF \
    -DLAVA_INSTALL=OFF >/dev/null
fi
targets="lava fuzz_scene fuzz_suite fuzz_checkpoint fuzz_cli"
# shellcheck disable=SC2086  # the targets, one word each
cmake --build "$dir" -j2 --target $targets >/dev/null || cmake --build "$dir" -j1 --target $targets
"$dir/lava" --version
findings=$dir/fuzz-findings
rm -rf "$findings"
mkdir -p "$findings"
run() {  # target: a working copy of its corpus (new inputs stay out of the repository)
  local target=$1 work=$findings/$1
  mkdir -p "$work/corpus"
  cp fuzz/corpus/"$target"/* fuzz/regressions/"$target"/* "$work/corpus/" 2>/dev/null || true
  # Every preset and module scene seeds the scene target too.
  [ "$target" = scene ] && for f in scenes/*.toml scenes/modules/*.toml; do
    cp "$f" "$work/corpus/preset-$(basename "$f")"
  done
  # The command line reads scene files by relative path: from the repository's root.
  if "$dir/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -malloc_limit_mb=2048 -dict=fuzz/lava.dict -close_fd_mask=3 -print_final_stats=1 \
       -artifact_prefix="$work/" "$work/corpus" > "$work/log.txt" 2>&1; then
    echo "fuzz_$target: $(grep -E '^stat::(number_of_executed_units|average_exec_per_sec)' \
      "$work/log.txt" | tr '\n' ' ')$(ls "$work/corpus" | wc -l) inputs in the corpus"
  else
    tail -30 "$work/log.txt"
    echo "FAIL: fuzz_$target found a problem: $(ls "$work"/crash-* "$work"/leak-* \
      "$work"/timeout-* "$work"/oom-* 2>/dev/null | tr '\n' ' ')"
    return 1
  fi
}
status=0
run scene & a=$!
run checkpoint & b=$!
wait $a || status=1
wait $b || status=1
run suite & a=$!
run cli & b=$!
wait $a || status=1
wait $b || status=1
[ $status -eq 0 ] && echo "fuzz: PASS"
exit $status
