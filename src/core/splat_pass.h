// The fast line renderer: splat.comp adds every alive particle's line into a fixed-point
// accumulation buffer the size of the target, and resolve.frag blends it over the scene
// inside the render pass. The graphics line pipeline stays the reference renderer.
#pragma once
#include <vector>

#include "buffer.h"
#include "context.h"
#include "gpu_simulator.h"
#include "shared.h"

namespace lava {

class SplatPass {
 public:
  SplatPass(Context& context, VkRenderPass renderPass, const GpuSimulator& simulator);
  void bind(const GpuSimulator& simulator);
  // Outside a render pass: clears the accumulation buffer and splats every chunk into it.
  void recordSplat(VkCommandBuffer commands, VkExtent2D extent, gpu::SplatParams params);
  // Inside the render pass, after the scenery.
  void recordResolve(VkCommandBuffer commands, const gpu::SplatParams& params) const;

 private:
  void resize(VkExtent2D extent);
  void writeSets();

  Context& context_;
  UniqueDescriptorSetLayout splatSetLayout_;
  UniqueDescriptorSetLayout resolveSetLayout_;
  UniquePipelineLayout splatLayout_;
  UniquePipelineLayout resolveLayout_;
  UniquePipeline splatPipeline_;
  UniquePipeline resolvePipeline_;
  std::vector<ParticleChunk> chunks_;  // the simulator's: their texel views (not their sets)
  VkExtent2D extent_{0, 0};
  Buffer accumulation_;
  UniqueDescriptorPool pool_;
  std::vector<VkDescriptorSet> splatSets_;  // one per particle chunk
  VkDescriptorSet resolveSet_ = VK_NULL_HANDLE;
};

}  // namespace lava
