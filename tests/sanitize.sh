#!/usr/bin/env bash
# Lava's core, program and tests built with AddressSanitizer and UndefinedBehaviorSanitizer
# (any report fails), then the test suite on lavapipe. Leak checking is on for the tests
# that do not load Vulkan; lavapipe's ICD, unloaded by the loader at vkDestroyInstance,
# leaks 128 bytes that LeakSanitizer cannot attribute, so it is off for the others.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DLAVA_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-asan -j2
ctest --test-dir build-asan --output-on-failure -R '^(Layout|Random|Physics|Emission|StateIo|Compare)\.'
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j2 -E 'Soak'
