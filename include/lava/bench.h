// The ceilings `lava bench` measures a backend against, on the same device in the same run.
#pragma once
#include <cstdint>

#include "device.h"
#include "export.h"

namespace lava {

// Bytes one unfused step moves per particle: the particle read and written (two vec4 each).
constexpr double kBytesPerUpdate = 64.0;

// Blocking. Seconds one pass of a copy kernel over `particles` particles takes on the GPU,
// chunked like a simulation (median of `passes` timed passes after a warm-up).
LAVA_API double gpuCopySeconds(Device& device, uint64_t particles, int passes = 9);
// Seconds `threads` CPU threads take to copy `particles` particles (median of `passes`).
LAVA_API double cpuCopySeconds(uint64_t particles, unsigned threads, int passes = 5);

}  // namespace lava
