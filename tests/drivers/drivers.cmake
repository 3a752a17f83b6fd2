# Included by tests/CMakeLists.txt. Every conforming implementation CI has (docs/drivers.md): lavapipe 22.3 (the default), lavapipe
# 25.0 and SwiftShader, which third_party/fetch-drivers.sh fetches into LAVA_DRIVERS_DIR,
# and lavapipe 22.3 in the minimal device profile (no push descriptors, 64-bit atomics or
# float-control declarations: the fallbacks, on any machine). On each, with validation on:
# the builtin suite against the CPU, its hashes against the other drivers', the GPU tests,
# both renderers' frames against lavapipe 22.3's, the embed example (Install.*) and the
# demo, headless.
set(LAVA_DRIVERS_DIR "$ENV{HOME}/.cache/lava/drivers" CACHE PATH
    "Where third_party/fetch-drivers.sh put lavapipe 25 and SwiftShader")
if(DEFINED ENV{LAVA_DRIVERS_DIR})
  set(LAVA_DRIVERS_DIR "$ENV{LAVA_DRIVERS_DIR}")
endif()
set(lavapipe25 ${LAVA_DRIVERS_DIR}/lavapipe-25.json)
set(swiftshader ${LAVA_DRIVERS_DIR}/swiftshader.json)
set(LAVA_DRIVER_NAMES Lavapipe22 Minimal)
if(EXISTS ${lavapipe25} AND EXISTS ${swiftshader})
  list(APPEND LAVA_DRIVER_NAMES Lavapipe25 SwiftShader)
  set(LAVA_EXTRA_ICDS ${lavapipe25} ${swiftshader})  # the install test runs examples/embed on them
elseif("$ENV{CI}" STREQUAL "true")
  message(FATAL_ERROR "no drivers in ${LAVA_DRIVERS_DIR}: run third_party/fetch-drivers.sh")
else()
  message(WARNING "lavapipe 25 and SwiftShader are not in ${LAVA_DRIVERS_DIR}: their tests are "
                  "not registered (third_party/install-deps.sh fetches them)")
endif()

set(env_Lavapipe22 VK_DRIVER_FILES=${LAVA_LAVAPIPE_ICD} VK_ICD_FILENAMES=${LAVA_LAVAPIPE_ICD})
set(env_Minimal ${env_Lavapipe22} LAVA_DEVICE_PROFILE=minimal)
set(env_Lavapipe25 VK_DRIVER_FILES=${lavapipe25} VK_ICD_FILENAMES=${lavapipe25})
set(env_SwiftShader VK_DRIVER_FILES=${swiftshader} VK_ICD_FILENAMES=${swiftshader})
# Which GPU tests run where (gtest filters; CI's whole run must stay under 40 minutes on a
# two-core host). The minimal profile: all of them but those named below. Lavapipe 25: those
# of the modules against the CPU, both renderers, the look and embedding; not the long runs
# of host-side logic (the soak, 2^31 births in a dispatch, 512 chunks, the limits of other
# vendors), which lavapipe 22 runs (and the minimal profile, 512 chunks and the limits). SwiftShader runs Lava's compute shaders far more
# slowly than lavapipe (docs/drivers.md): there, both renderers, two tests of the
# look and embedding; its builtin suite compares every module with the CPU and crosses 129
# chunks. It has no 64-bit atomics (*Pairs*) and no host-memory render targets. The flow's
# pool physics on lavapipe run once, on lavapipe 22.3's default profile (the minimal one runs
# the flow's other tests, bit for bit against the CPU), and so do the soak of a million steps
# and 2^31 births in a dispatch (host logic that no profile changes: a minute each).
# Neither runs Effects/Modules.*: their builtin suites compare the same module scenes with the
# CPU at 0 ULP, and resuming from a checkpoint is host code that no driver changes; so is the
# implicit flow, which the GPU backend steps on the host (lavapipe 22.3 runs its test).
set(filter_Minimal
    "*-GpuFlow.APool*:GpuFlow.AHotter*:GpuFlow.NoParticle*:GpuTest.SoakOfAMillionSteps*:GpuTest.ADispatchOfMoreThan2To31BirthsIsSplit:Effects/Modules.*:GpuTest.CpuThreadCounts*:GpuFlow.TheImplicitFlowIsSteppedOnTheHost*")
set(filter_Lavapipe25 "RenderTest.*:LookTest.*:GlowCells.*:EmbeddingDraw.*:GpuTest.Seed*:GpuTest.LoadAndState*:GpuTest.RandomScenes*:GpuTest.SerialCarry*:DescriptorArena.*")
# The builtin suite's cases each runs (all where none are named). SwiftShader takes 12 times
# lavapipe's time over the suite (500 s on a 2-vCPU Xeon): there, "all" stands for the
# modules it combines (every collider, both forces, bursts and lifetimes, three emitter
# shapes, velocity Verlet), with the seed scene, the flow (whose sparks step by the other
# integrator, semi-implicit Euler), denormals and the host's bookkeeping where it reaches the
# shader (rings wrapping in a dispatch, serials past 2^32, chunks past a binding:
# SwiftShader's are the smallest); the point emitter and fractional rates are the same shader
# code as those (docs/drivers.md).
string(JOIN "," swiftshader_cases seed-scene all flow ring-wraps-within-a-dispatch
            denormals-flushed serial-crosses-2^32 beyond-one-binding)
set(cases_SwiftShader --cases ${swiftshader_cases})
# Its render tests: those of clipping, the splat's tiles, the glow and the cached backdrop;
# the colour ramps' tests are the same fragment arithmetic on every driver (lavapipe 25 runs
# them all), and its frames of both renderers are compared with lavapipe 22.3's below.
string(JOIN ":" swiftshader_render RenderTest.LinesLeavingTheView* RenderTest.SplatAndPipeline*
            RenderTest.SplatDrawsLinesAcrossResolveTiles RenderTest.CachedBackdrop*)
set(filter_SwiftShader
    "${swiftshader_render}:LookTest.LinesAndSplatAgree:LookTest.SplatHidesWhatTheConeHides:LookTest.ASettledPoolIsOneContinuousSurface:EmbeddingDraw.*:-*Pairs*:*HostMemoryTarget*")

# How far each one's frames may stray from lavapipe 22.3's, "N:L" (at most N pixels differ by
# more than L levels) for the splat, then the lines; docs/drivers.md gives the measurements
# and the causes: line rasterization, and the backdrop's fragment shading, which Vulkan
# does not define to the bit.
# The eruption's frames (its molten surface, at 640x360) take the volcano's tolerances:
# SwiftShader's differ in 822 and 1,487 of their 230,400 pixels beyond 2 levels (2026-12-07).
set(frames_Minimal 0:0 0:0 0:0 0:0)
set(frames_Lavapipe25 0:0 200:0 0:0 200:0)
set(frames_SwiftShader 2000:2 8000:2 2000:2 8000:2)

add_executable(lava_image_diff ${CMAKE_CURRENT_LIST_DIR}/image_diff.cpp)
target_link_libraries(lava_image_diff PRIVATE lava_stb lava_warnings)

set(out ${CMAKE_CURRENT_BINARY_DIR}/drivers)
file(MAKE_DIRECTORY ${out})
set(script ${CMAKE_CURRENT_LIST_DIR}/drivers_test.sh)
set(hashes "")
foreach(name ${LAVA_DRIVER_NAMES})
  set(env ${env_${name}} LAVA_VALIDATION=1)
  # The builtin suite against the CPU at tolerance 0, recording its hashes.
  add_test(NAME Drivers.${name}.BuiltinSuite
           COMMAND $<TARGET_FILE:lava> validate --suite builtin ${cases_${name}}
                   --record ${out}/${name}.csv --junit ${out}/${name}.xml)
  set_tests_properties(Drivers.${name}.BuiltinSuite PROPERTIES ENVIRONMENT "${env}"
                       FIXTURES_SETUP hashes-${name} TIMEOUT 900 LABELS drivers)
  list(APPEND hashes ${out}/${name}.csv)
  # Both renderers' frames of the volcano and of the eruption's molten surface, to be
  # compared with lavapipe 22.3's.
  add_test(NAME Drivers.${name}.RenderBothRenderers
           COMMAND ${script} render $<TARGET_FILE:lava> ${PROJECT_SOURCE_DIR}/scenes
                   ${out}/frames-${name})
  set_tests_properties(Drivers.${name}.RenderBothRenderers PROPERTIES ENVIRONMENT "${env}"
                       FIXTURES_SETUP frames-${name} TIMEOUT 600 LABELS drivers)
  add_test(NAME Drivers.${name}.DemoHeadless
           COMMAND $<TARGET_FILE:lava> demo --headless --frames 10 --size 320x180)
  set_tests_properties(Drivers.${name}.DemoHeadless PROPERTIES ENVIRONMENT "${env}"
                       WORKING_DIRECTORY ${out}/demo-${name} TIMEOUT 300 LABELS drivers)
  file(MAKE_DIRECTORY ${out}/demo-${name})
  if(NOT name STREQUAL "Lavapipe22")  # lavapipe 22.3's own GPU tests are lava_gpu_tests'
    gtest_discover_tests(lava_gpu_tests TEST_PREFIX "Drivers.${name}." TEST_FILTER
                         "${filter_${name}}" PROPERTIES ENVIRONMENT "${env}" LABELS drivers
                         TIMEOUT 900 DISCOVERY_TIMEOUT 60)
    add_test(NAME Drivers.${name}.FramesMatchLavapipe22
             COMMAND ${script} compare $<TARGET_FILE:lava_image_diff> ${out}/frames-Lavapipe22
                     ${out}/frames-${name} ${frames_${name}})
    set_tests_properties(Drivers.${name}.FramesMatchLavapipe22 PROPERTIES
                         FIXTURES_REQUIRED "frames-Lavapipe22;frames-${name}" LABELS drivers)
  endif()
endforeach()

# GPU against GPU: every case's hashes equal on every driver (those of the cases a driver
# runs), and `--against` one run.
add_test(NAME Drivers.HashesAgreeAcrossDrivers COMMAND ${script} hashes ${hashes})
set(fixtures "")
foreach(name ${LAVA_DRIVER_NAMES})
  list(APPEND fixtures hashes-${name})
endforeach()
set_tests_properties(Drivers.HashesAgreeAcrossDrivers PROPERTIES FIXTURES_REQUIRED "${fixtures}"
                     LABELS drivers)
if(Lavapipe25 IN_LIST LAVA_DRIVER_NAMES)
  add_test(NAME Drivers.Lavapipe25.AgainstLavapipe22Hashes
           COMMAND $<TARGET_FILE:lava> validate --suite builtin --cases seed-scene,all,flow
                   --against ${out}/Lavapipe22.csv)
  set_tests_properties(Drivers.Lavapipe25.AgainstLavapipe22Hashes PROPERTIES
                       ENVIRONMENT "${env_Lavapipe25};LAVA_VALIDATION=1"
                       FIXTURES_REQUIRED hashes-Lavapipe22 TIMEOUT 600 LABELS drivers)
endif()
