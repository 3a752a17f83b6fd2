// The ceilings `lava bench` measures a backend against, on the same device in the same run.
#pragma once
#include <cstdint>
#include <string>

#include <vector>

#include "device.h"
#include "export.h"
#include "simulation.h"
#include "state.h"

namespace lava {

// Bytes one unfused step moves per particle: the particle read and written (two vec4 each).
constexpr double kBytesPerUpdate = 64.0;

// Blocking. Seconds one pass of a copy kernel over `particles` particles takes on the GPU,
// chunked like a simulation (median of `passes` timed passes after a warm-up).
LAVA_API double gpuCopySeconds(Device& device, uint64_t particles, int passes = 9);
// Seconds `threads` CPU threads take to copy `particles` particles (median of `passes`).
LAVA_API double cpuCopySeconds(uint64_t particles, unsigned threads, int passes = 5);

// Blocking (the GPU's: submits and waits). The compute ceilings: updates/s of a backend's
// steps alone, with no emission and no memory traffic, from `start` (the state a timed run starts from) for `steps` steps.
// GPU: step.comp's steps (the scene's modules) for all of `start`, read and written once
// per pass. CPU: the kernel's own loop on `threads` threads, each stepping blocks of
// `start` that never leave L1. Medians of `passes` (CPU: of about `seconds` each).
LAVA_API double gpuComputeUpdatesPerSecond(Device& device, const Scene& scene,
                                           const std::vector<Particle>& start, uint32_t steps,
                                           int passes = 3);
// `simdTarget` as CpuSimulation's.
LAVA_API double cpuComputeUpdatesPerSecond(const Scene& scene, const std::vector<Particle>& start,
                                           uint64_t steps, unsigned threads, CpuKernel kernel,
                                           int passes = 3, double seconds = 0.15,
                                           const std::string& simdTarget = "");

}  // namespace lava
