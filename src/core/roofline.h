// Copy kernels that give `lava bench` its roofline: the bandwidth a kernel moving the same
// bytes as one simulation step reaches on the same device, in the same run.
#pragma once
#include <cstdint>

#include <utility>
#include <vector>

#include "buffer.h"
#include "context.h"

namespace lava {

// copy.comp from one buffer of particles into another, chunked like the simulation.
class CopyKernel {
 public:
  CopyKernel(const Context& context, const Buffer& source, const Buffer& destination,
             uint32_t particles);
  // Records the dispatches only: the caller owns the barriers around them.
  void record(VkCommandBuffer commands) const;

 private:
  UniqueDescriptorSetLayout setLayout_;
  UniquePipelineLayout layout_;
  UniquePipeline pipeline_;
  UniqueDescriptorPool pool_;
  std::vector<std::pair<VkDescriptorSet, uint32_t>> sets_;  // set, particles in its range
};

// Seconds the GPU takes for one pass of copy.comp over `particles` particles (median of
// `passes` timed passes, after a warm-up).
double gpuCopySeconds(Context& context, uint32_t particles, int passes = 9);

// Seconds `threads` CPU threads take to copy `particles` particles (median of `passes`).
double cpuCopySeconds(uint32_t particles, unsigned threads, int passes = 5);

}  // namespace lava
