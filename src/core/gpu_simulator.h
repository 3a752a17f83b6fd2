// The Vulkan backend: step.comp over the particles, held in chunks of at most one binding's
// range (maxStorageBufferRange) and one allocation, each its own device-local buffer; many
// steps per dispatch and many dispatches per submit.
#pragma once
#include <vector>

#include "buffer.h"
#include "context.h"
#include "simulator.h"
#include "timestamps.h"

namespace lava {

// Particles [first, first + count), the buffer that holds them (from offset 0), its view as
// RGBA32F texels (posAge, velMass per particle) and, in the simulator, the descriptor set
// that binds it for step.comp.
struct ParticleChunk {
  uint32_t first;
  uint32_t count;
  VkBuffer buffer;
  VkBufferView texels = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
};

// Particles one chunk holds on this device: one binding, one dispatch and one allocation
// cover it (a workgroup multiple).
uint32_t particlesPerChunk(const Context& context);
// Largest particle count this device allows: its largest device-local heap (chunks are
// separate allocations), at most 2^31.
uint64_t maxParticles(const Context& context);

class GpuSimulator final : public Simulator {
 public:
  GpuSimulator(Context& context, const Scene& scene);
  void advance(uint64_t steps) override;
  // advance() that also returns the GPU time of the steps (timestamp queries), in seconds.
  double advanceTimed(uint64_t steps);
  // Steps one dispatch fuses (1..kStepsPerDispatch): fewer moves more memory per step.
  void setStepsPerDispatch(uint32_t steps) { stepsPerDispatch_ = steps; }
  SimState state() override;
  void load(const SimState& state) override;

  // Plans the next `count` steps into schedule entries [first, first + count): the host's
  // ring bookkeeping. Entries still read by a submitted frame must not be planned over.
  void planSteps(uint32_t first, uint32_t count);
  // Records those steps (after planSteps) for submission by the caller.
  void recordSteps(VkCommandBuffer commands, uint32_t first, uint32_t count) const;
  // Changes parameters that keep the capacity (the demo's live controls).
  void setScene(const Scene& scene);
  // The particles, chunk by chunk (renderers bind the same buffers).
  const std::vector<ParticleChunk>& chunks() const { return chunks_; }
  const EmissionClock& clock() const { return clock_; }

  static constexpr uint32_t kStepsPerDispatch = 256;
  static constexpr uint32_t kStepsPerSubmit = 4096;

 private:
  Context& context_;
  EmissionClock clock_;
  std::vector<Buffer> particles_;  // one per chunk
  Buffer staging_;                 // one chunk's worth, for load() and state()
  Buffer schedule_;
  UniqueDescriptorSetLayout setLayout_;
  UniquePipelineLayout pipelineLayout_;
  UniquePipeline pipeline_;
  UniqueDescriptorPool descriptorPool_;
  std::vector<ParticleChunk> chunks_;
  std::vector<UniqueBufferView> texelViews_;  // per chunk: its particles as RGBA32F texels
  std::vector<uint64_t> planned_;
  uint32_t stepsPerDispatch_ =
      kStepsPerDispatch;  // births before each planned entry (host copy of sums.x)
};

}  // namespace lava
