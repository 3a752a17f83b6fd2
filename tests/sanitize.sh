#!/usr/bin/env bash
# Lava's library, program, examples and tests built with AddressSanitizer and
# UndefinedBehaviorSanitizer (any report fails), then the test suite on lavapipe, in three
# runs:
#   1. the tests that load no Vulkan (the flow's included, but for its three longest physics
#      runs), with leak checking;
#   2. the others with the validation layer (not the other drivers' tests: the same code
#      of Lava's; the embedding tests take the descriptor sets' path; nor the long runs
#      listed below, the plain suite's), leak checking off: the loader unloads the validation layer
#      and lavapipe's ICD at vkDestroyInstance, and what they keep until then can no longer
#      be attributed to them (LeakSanitizer reports it as ours);
#   3. the program's tests (label "program": build/lava run as users run it, the
#      fault-injection tables included but the headless demo's, below) with leak checking
#      on: lavapipe and Lava's fault
#      layer are preloaded so that they stay mapped and their frames symbolised,
#      tests/lsan.supp names the system libraries whose own allocations are theirs, and the
#      validation layer is off (the plain suite runs these tests with it). A leak in Lava on
#      any path, error paths included, fails the run. Twelve gtest shards, two at a time.
# The Python module is left out of this build: an instrumented extension needs the
# sanitizer runtime preloaded into python3 itself.
# It is Debian's clang++ with every warning an error (the code is not GCC's alone; the plain
# build is GCC's), and it builds the fuzz targets too (LAVA_FUZZ): tests/fuzz.sh runs them
# from this build, which spares CI a third build of the library.
set -euo pipefail
cd "$(dirname "$0")/.."
# Line tables only (-g1): the reports' frames name file and line, and the build takes less
# of CI's time than with full debug information.
CC=clang CXX=clang++ cmake -S . -B build-asan -DLAVA_SANITIZE=ON -DLAVA_FUZZ=ON \
      -DLAVA_BUILD_PYTHON=OFF -DCMAKE_CXX_FLAGS=-Werror \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" \
      >/dev/null
cmake --build build-asan -j2 || cmake --build build-asan -j1  # the second shows the error
# The groups of the tests that load no Vulkan.
novulkan='Random|Physics|Emission|StateIo|Compare|Integrators|Forces|Colliders|Denormals|SceneKeys|SceneToml|Spirv|Simd|Effects/SimdModules|FlowKeys|FlowState|FlowPhysics|FlowImplicit'
# The flow's longest physics (a pool's spreading over seconds) are the plain suite's: the
# same host code as the shorter flow tests here, at 4 times the time. So are the SIMD
# kernels' bit-for-bit checks of each module on its own and of random scenes: every module
# runs through the same kernels in the "all" scene, which runs here (with the flow's). The
# wide-radius block (21 s here) takes the same host code as the pools here, with longer lists.
# So do each instruction set's kernels (36 s here, 25 times the plain suite's: Highway's
# targets are one source, whose best target runs here in Effects/SimdModules) and the boxes
# standing on the ground (31 s, ten times: the same contact code as the other Colliders here).
physics='^FlowPhysics\.(APool|AHotter|TheLessViscous)|^FlowImplicit\.(ThreadCounts|AHotter|APoolReleased|OnAPlane|TheLessViscous|ABlockWithAWide)|^Simd\.(RandomScenes|EveryInstructionSet)'
physics+='|^Colliders\.NothingEndsAStepInsideABoxStandingOnTheGround'
modules='[^ ]*/(bursts|collider|emitter|force|integrator)'
ctest --test-dir build-asan --output-on-failure -j2 -R "^($novulkan)\\." \
      -E "$physics|^Effects/SimdModules\\.$modules"
# Left to the plain suite, whose runs of them take the same host code as the shorter tests
# here: the flow's pool physics and module scene and the soak of a million steps (lavapipe's
# time, not the host's), 2^31 births in a dispatch (the births tests' split, 4 minutes under
# the sanitizers on a 2-vCPU Xeon), the runbook's dry run (the program's commands, which run
# 3 takes under the sanitizers) and the examples built against an installed copy (a
# compiler's time). The pattern is a CMake
# regular expression: one backslash before a literal dot.
long='^Effects/Modules\.AreBitIdenticalToTheCpuReference/flow |^GpuFlow\.(FlowSlotsAcross|APool|AHotter)'
long+='|^GpuTest\.(SoakOfAMillionSteps|ADispatchOfMoreThan2To31Births)|^(Runbook|Install)\.'
# And, as in the first run, each module on its own (the "all" scene and the flow's run
# here) and the CPU's thread counts (the SIMD kernels' own tests run them on one and two).
long+="|^Effects/Modules\\.$modules|^GpuTest\\.CpuThreadCounts"
# And the GPU-against-CPU runs of random scenes, of many emitters' births and of resuming the
# "all" scene: the host code of each is in the shorter tests here, the CPU reference's time
# four times over.
long+='|^GpuTest\.(RandomScenes|BirthsOfManyEmitters)|^Effects/Modules\.Resume[^ ]*/all '
# And the implicit flow on the GPU backend: the host's stepper, which the FlowImplicit tests
# in the first run take, and copies (the third run's render and demo --backend gpu take it).
long+='|^GpuFlow\.TheImplicitFlowIsSteppedOnTheHost'
# And the longest GPU runs of host code that shorter tests here take too: 512 chunks (the
# limits' tests chunk as each vendor would) and the flow's standing boxes and tilted pool (its
# grid, point burst and lattice tests run the same passes).
long+='|^GpuTest\.ManyChunksPastTheStorageBufferRange|^GpuFlow\.(BoxesStanding|AReleasedPool)'
# And the molten surface's looks but one: the same recording as the continuous pool's.
long+='|^LookTest\.(HotLiquid|CrustIsDark|HotRockLights|SparksInFront|RockHides)'
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j2 -LE program \
      -E "^(Drivers|$novulkan)\\.|$long"
icd=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' \
      "${LAVA_LAVAPIPE_ICD:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}")
echo "sanitize: the program's tests with leak checking (preloaded: $icd, the fault layer)"
# Twelve gtest shards, two at a time, each taken by whichever core is free: the fault-injection
# tables are long, and two fixed halves finished minutes apart; six shards of 100 to 311 s
# (stop 63) still left a core idle for 100 s at the end. Their runs are short programs
# (0.3 s each without the sanitizers) that allocate and free hundreds of megabytes compiling
# lavapipe's pipelines. Freed memory is held back 8 MB deep (256 by default) and new blocks are
# not filled: a use after free is still caught unless 8 MB were freed in between, and each run
# is a quarter shorter (render's: 1.5 s, 1.1 s).
shard() {
  env VK_DRIVER_FILES="${LAVA_LAVAPIPE_ICD:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}" \
      LAVA_VALIDATION=0 GTEST_TOTAL_SHARDS=12 GTEST_SHARD_INDEX=$1 GTEST_FILTER="-$slow" \
      LD_PRELOAD="$icd $PWD/build-asan/tests/fault/liblava_fault_layer.so" \
      ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0:quarantine_size_mb=8:max_malloc_fill_size=0 \
      LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp \
      build-asan/tests/lava_cli_tests > "build-asan/cli-shard-$1.log" 2>&1
}
# Left to the plain suite: the progress display's long runs on a terminal, the builtin
# suite's reports (the suite's code runs here in the other Suite tests), the flow's
# published solutions (minutes of the CPU reference; StudyFlow runs the same commands) and
# the headless demo's fault-injection table (228 s here): 132 of its 136 call sites are the
# render table's, whose failures run here (the renderers, the device, the frame loop's
# submissions and read-backs).
slow='Progress.*:Suite.BuiltinPassesWithParsableReports:PublishedSolutions.*'
slow+=':Commands/FaultInjection.EveryFailingCallExitsOneWithOneLineAndNoPartialOutput/demo'
export -f shard
export slow
export icd
status=0
seq 0 11 | xargs -P 2 -I{} bash -c 'shard {}' || status=1
for k in $(seq 0 11); do
  if [ $status -ne 0 ]; then cat "build-asan/cli-shard-$k.log"; else tail -n 3 "build-asan/cli-shard-$k.log"; fi
done
exit $status
