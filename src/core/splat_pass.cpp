#include "splat_pass.h"

#include "descriptors.h"
#include "pipeline.h"
#include "resolve_frag.h"
#include "resolve_vert.h"
#include "splat_comp.h"
#include "vk_check.h"

namespace lava {

SplatPass::SplatPass(Context& context, VkRenderPass renderPass, const GpuSimulator& simulator)
    : context_(context) {
  VkDevice device = context.device();
  splatSetLayout_ = createSetLayout(
      device, {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  resolveSetLayout_ = createStorageSetLayout(device, 1, VK_SHADER_STAGE_FRAGMENT_BIT);
  splatLayout_ = createPipelineLayout(device, splatSetLayout_, VK_SHADER_STAGE_COMPUTE_BIT,
                                      sizeof(gpu::SplatParams));
  resolveLayout_ = createPipelineLayout(device, resolveSetLayout_, VK_SHADER_STAGE_FRAGMENT_BIT,
                                        sizeof(gpu::SplatParams));
  splatPipeline_ = createComputePipeline(device, splatLayout_, kSplatCompSpv, sizeof(kSplatCompSpv),
                                         gpu::kWorkgroupSize);
  GraphicsPipelineDesc resolve{kResolveVertSpv, sizeof(kResolveVertSpv), kResolveFragSpv,
                               sizeof(kResolveFragSpv)};
  resolve.additive = true;
  resolve.depthTest = false;
  resolve.depthWrite = false;
  resolvePipeline_ = createGraphicsPipeline(device, resolveLayout_, renderPass, resolve);
  bind(simulator);
}

void SplatPass::bind(const GpuSimulator& simulator) {
  chunks_ = simulator.chunks();
  if (extent_.width != 0) writeSets();
}

void SplatPass::resize(VkExtent2D extent) {
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  VK_CHECK(vkDeviceWaitIdle(context_.device()));  // the old buffer may still be read
  extent_ = extent;
  accumulation_ = Buffer(context_, VkDeviceSize{extent.width} * extent.height * sizeof(uint32_t),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  writeSets();
}

void SplatPass::writeSets() {
  VkDevice device = context_.device();
  const uint32_t chunks = static_cast<uint32_t>(chunks_.size());
  pool_ = createPool(device, chunks + 1,
                     {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, chunks},
                      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunks + 1}});
  const VkDescriptorBufferInfo accumulation{accumulation_.get(), 0, VK_WHOLE_SIZE};
  splatSets_.clear();
  for (const ParticleChunk& chunk : chunks_) {
    const VkDescriptorSet set = allocateSet(device, pool_, splatSetLayout_);
    writeTexels(device, set, 0, chunk.texels);
    writeStorage(device, set, 1, accumulation);
    splatSets_.push_back(set);
  }
  resolveSet_ = allocateSet(device, pool_, resolveSetLayout_);
  writeStorage(device, resolveSet_, 0, accumulation);
}

void SplatPass::recordSplat(VkCommandBuffer commands, VkExtent2D extent, gpu::SplatParams params) {
  resize(extent);
  // WAR: the previous frame's resolve.frag read the sums this fill clears.
  memoryBarrier(commands, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                0);
  vkCmdFillBuffer(commands, accumulation_.get(), 0, VK_WHOLE_SIZE, 0);
  // RAW/WAW: splat.comp adds atomically into the cleared sums.
  memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, splatPipeline_);
  params.target.x = extent.width;
  params.target.y = extent.height;
  for (size_t c = 0; c < chunks_.size(); ++c) {
    params.target.z = chunks_[c].count;
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, splatLayout_, 0, 1,
                            &splatSets_[c], 0, nullptr);
    vkCmdPushConstants(commands, splatLayout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                       &params);
    vkCmdDispatch(commands, (chunks_[c].count + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1,
                  1);
  }
  // RAW: resolve.frag reads the sums splat.comp wrote.
  memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
}

void SplatPass::recordResolve(VkCommandBuffer commands, const gpu::SplatParams& params) const {
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, resolvePipeline_);
  vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, resolveLayout_, 0, 1,
                          &resolveSet_, 0, nullptr);
  gpu::SplatParams p = params;
  p.target.x = extent_.width;
  p.target.y = extent_.height;
  vkCmdPushConstants(commands, resolveLayout_, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(p), &p);
  vkCmdDraw(commands, 3, 1, 0, 0);
}

}  // namespace lava
