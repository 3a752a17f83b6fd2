#!/usr/bin/env bash
# Lava's library, program, examples and tests built with AddressSanitizer and
# UndefinedBehaviorSanitizer (any report fails), then the test suite on lavapipe, in three
# runs:
#   1. the tests that load no Vulkan (the flow's included), with leak checking;
#   2. the others with the validation layer (not the other drivers' tests: the same code
#      of Lava's; the embedding tests take the descriptor sets' path; nor the soak of a
#      million steps, which runs the host code of a thousand-step test a thousand times and
#      is the plain suite's), leak checking off: the loader unloads the validation layer
#      and lavapipe's ICD at vkDestroyInstance, and what they keep until then can no longer
#      be attributed to them (LeakSanitizer reports it as ours);
#   3. the program's tests (label "program": build/lava run as users run it, the
#      fault-injection table included) with leak checking on: lavapipe and Lava's fault
#      layer are preloaded so that they stay mapped and their frames symbolised,
#      tests/lsan.supp names the system libraries whose own allocations are theirs, and the
#      validation layer is off (the plain suite runs these tests with it). A leak in Lava on
#      any path, error paths included, fails the run. Two gtest shards run side by side.
# The Python module is left out of this build: an instrumented extension needs the
# sanitizer runtime preloaded into python3 itself.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DLAVA_SANITIZE=ON -DLAVA_BUILD_PYTHON=OFF \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-asan -j2
# The groups of the tests that load no Vulkan.
novulkan='Random|Physics|Emission|StateIo|Compare|Integrators|Forces|Colliders|Denormals|SceneKeys|SceneToml|Spirv|Simd|Effects/SimdModules|FlowKeys|FlowState|FlowPhysics'
ctest --test-dir build-asan --output-on-failure -j2 -R "^($novulkan)\\."
# The flow's longest GPU runs (lavapipe's time, not the host's) are left to the plain suite:
# its other GPU tests take the same host code (its buffers, passes and read-backs).
longFlow='^Effects/Modules\\.AreBitIdenticalToTheCpuReference/flow |^GpuFlow\\.(FlowSlotsAcross|APool|AHotter)'
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j2 -LE program \
      -E "^(Drivers|$novulkan)\\.|^GpuTest\\.SoakOfAMillionSteps|$longFlow"
icd=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' \
      "${LAVA_LAVAPIPE_ICD:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}")
echo "sanitize: the program's tests with leak checking (preloaded: $icd, the fault layer)"
shard() {
  env VK_DRIVER_FILES="${LAVA_LAVAPIPE_ICD:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}" \
      LAVA_VALIDATION=0 GTEST_TOTAL_SHARDS=2 GTEST_SHARD_INDEX=$1 \
      LD_PRELOAD="$icd $PWD/build-asan/tests/fault/liblava_fault_layer.so" \
      ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0 \
      LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp \
      build-asan/tests/lava_cli_tests > "build-asan/cli-shard-$1.log" 2>&1
}
shard 0 & first=$!
shard 1 & second=$!
status=0
wait $first || status=1
wait $second || status=1
for k in 0 1; do
  if [ $status -ne 0 ]; then cat "build-asan/cli-shard-$k.log"; else tail -n 3 "build-asan/cli-shard-$k.log"; fi
done
exit $status
