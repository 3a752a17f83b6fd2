// Storage-buffer descriptor plumbing shared by every pipeline: set layouts, pipeline
// layouts with one push-constant range, pools and sets.
#pragma once
#include "unique.h"

namespace lava {

// Bindings 0 .. count-1, each one storage buffer visible to `stages`.
UniqueDescriptorSetLayout createStorageSetLayout(VkDevice device, uint32_t count,
                                                 VkShaderStageFlags stages);
UniquePipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes);
UniqueDescriptorPool createStoragePool(VkDevice device, uint32_t sets, uint32_t descriptors);
VkDescriptorSet allocateSet(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);
void writeStorage(VkDevice device, VkDescriptorSet set, uint32_t binding,
                  const VkDescriptorBufferInfo& range);

// One global memory barrier; callers name the hazard in a comment.
void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

}  // namespace lava
