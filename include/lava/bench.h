// In liblava_tools (Lava::lava_tools, pkg-config lava_tools), beside liblava.
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
LAVA_TOOLS_API double gpuCopySeconds(Device& device, uint64_t particles, int passes = 9);
// Seconds `threads` CPU threads take to copy `particles` particles (median of `passes`).
LAVA_TOOLS_API double cpuCopySeconds(uint64_t particles, unsigned threads, int passes = 5);

// Blocking (the GPU's: submits and waits). The compute ceilings: updates/s of a backend's
// steps alone, with no emission and no memory traffic, from `start` (the state a timed run starts from) for `steps` steps.
// GPU: step.comp's steps (the scene's modules) for all of `start`, read and written once
// per pass. CPU: the kernel's own loop on `threads` threads, each stepping blocks of
// `start` that never leave L1. Medians of `passes` (CPU: of about `seconds` each).
LAVA_TOOLS_API double gpuComputeUpdatesPerSecond(Device& device, const Scene& scene,
                                           const std::vector<Particle>& start, uint32_t steps,
                                           int passes = 3);
// `simdTarget` as CpuSimulation's.
LAVA_TOOLS_API double cpuComputeUpdatesPerSecond(const Scene& scene, const std::vector<Particle>& start,
                                           uint64_t steps, unsigned threads, CpuKernel kernel,
                                           int passes = 3, double seconds = 0.15,
                                           const std::string& simdTarget = "");

// The flow's neighbour lists of `state`: for each alive flow particle, in state order, the
// alive flow particles within the flow's radius (docs/model.md's pair test), itself excluded.
struct FlowNeighbours {
  std::vector<Particle> particles;  // the alive flow particles
  std::vector<uint32_t> starts;     // particle i's neighbours: lists[starts[i], starts[i + 1])
  std::vector<uint32_t> lists;      // indices into `particles`
};
LAVA_TOOLS_API FlowNeighbours flowNeighbours(const Scene& scene, const State& state);

// Blocking (the GPU's: submits and waits). The flow's ceilings: neighbour pairs per second of
// the density sum over `neighbours` alone, with no grid and no sort (medians of `passes`).
LAVA_TOOLS_API double gpuFlowPairsPerSecond(Device& device, const Scene& scene,
                                      const FlowNeighbours& neighbours, int passes = 5);
LAVA_TOOLS_API double cpuFlowPairsPerSecond(const Scene& scene, const FlowNeighbours& neighbours,
                                      unsigned threads, int passes = 5);

}  // namespace lava
