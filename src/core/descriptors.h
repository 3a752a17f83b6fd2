// Descriptor plumbing shared by every pipeline: set layouts, pipeline layouts with one
// push-constant range, pools and sets of storage buffers and uniform texel buffers.
#pragma once
#include <vector>

#include "unique.h"

namespace lava {

// Bindings 0 .. count-1, each one storage buffer visible to `stages`.
UniqueDescriptorSetLayout createStorageSetLayout(VkDevice device, uint32_t count,
                                                 VkShaderStageFlags stages);
// Binding b of type types[b], each visible to `stages`.
UniqueDescriptorSetLayout createSetLayout(VkDevice device,
                                          const std::vector<VkDescriptorType>& types,
                                          VkShaderStageFlags stages);
UniquePipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes);
UniqueDescriptorPool createStoragePool(VkDevice device, uint32_t sets, uint32_t descriptors);
UniqueDescriptorPool createPool(VkDevice device, uint32_t sets,
                                const std::vector<VkDescriptorPoolSize>& sizes);
VkDescriptorSet allocateSet(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);
void writeStorage(VkDevice device, VkDescriptorSet set, uint32_t binding,
                  const VkDescriptorBufferInfo& range);
// A view of `range` bytes of `buffer` as RGBA32F texels (a uniform texel buffer).
UniqueBufferView createTexelView(VkDevice device, VkBuffer buffer, VkDeviceSize range);
void writeTexels(VkDevice device, VkDescriptorSet set, uint32_t binding, VkBufferView view);

// One global memory barrier; callers name the hazard in a comment.
void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);
// One image barrier over the single mip and layer of `image`, with a layout change.
void imageBarrier(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

}  // namespace lava
