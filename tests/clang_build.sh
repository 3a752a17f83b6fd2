#!/usr/bin/env bash
# The library and the program built with Debian's clang++ as well (CI's third step), with
# Lava's warnings on and every warning an error: the code is not GCC's alone.
# Usage: tests/clang_build.sh [BUILD_DIR]   (default build-clang)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-clang}
CC=clang CXX=clang++ cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-Werror \
  -DLAVA_BUILD_TESTS=OFF -DLAVA_BUILD_PYTHON=OFF >/dev/null
cmake --build "$dir" -j2
"$dir/lava" --version
echo "clang build: PASS"
