// Copy kernels that give `lava bench` its roofline: the bandwidth a kernel moving the same
// bytes as one simulation step reaches on the same device, in the same run.
#pragma once
#include <cstdint>

#include "buffer.h"
#include "context.h"

namespace lava {

// Seconds the GPU takes for one pass of copy.comp over `particles` particles (median of
// `passes` timed passes, after a warm-up).
double gpuCopySeconds(Context& context, uint32_t particles, int passes = 9);

// Seconds `threads` CPU threads take to copy `particles` particles (median of `passes`).
double cpuCopySeconds(uint32_t particles, unsigned threads, int passes = 5);

}  // namespace lava
