// Descriptors and barriers as Lava records them: push descriptors (no pools, no sets: each
// consumer pushes the buffers it reads), and one helper per barrier kind. Callers name the
// hazard of each barrier in a comment.
#pragma once
#include <array>
#include <initializer_list>

#include "device_context.h"
#include "unique.h"

namespace lava::detail {

// A push-descriptor set layout: binding b of types[b], each visible to `stages`; combined
// image samplers use `sampler` (immutable) when it is given.
UniqueDescriptorSetLayout createPushLayout(const DeviceContext& context,
                                           std::initializer_list<VkDescriptorType> types,
                                           VkShaderStageFlags stages,
                                           VkSampler sampler = VK_NULL_HANDLE);
// A sampler clamping to the edge, with `filter` for both magnification and minification.
UniqueSampler createSampler(const DeviceContext& context, VkFilter filter);
// One set layout (or none) and one push-constant range of `pushBytes` for `pushStages`.
UniquePipelineLayout createPipelineLayout(const DeviceContext& context, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes);

// Up to eight descriptor writes, pushed at once.
class PushDescriptors {
 public:
  PushDescriptors& buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                          VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE);
  PushDescriptors& texels(uint32_t binding, VkBufferView view);
  PushDescriptors& image(uint32_t binding, VkDescriptorType type, VkImageView view,
                         VkImageLayout layout, VkSampler sampler = VK_NULL_HANDLE);
  void push(const DeviceContext& context, VkCommandBuffer commands, VkPipelineBindPoint point,
            VkPipelineLayout layout) const;

 private:
  static constexpr size_t kMax = 8;
  std::array<VkWriteDescriptorSet, kMax> writes_{};
  std::array<VkDescriptorBufferInfo, kMax> buffers_{};
  std::array<VkDescriptorImageInfo, kMax> images_{};
  std::array<VkBufferView, kMax> views_{};
  size_t count_ = 0;
  VkWriteDescriptorSet& next(uint32_t binding, VkDescriptorType type);
};

// One global memory barrier.
void memoryBarrier(const DeviceContext& context, VkCommandBuffer commands,
                   VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);
// One image barrier over the single mip and layer of `image`, with a layout change.
void imageBarrier(const DeviceContext& context, VkCommandBuffer commands, VkImage image,
                  VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                  VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

// Workgroups of `groupSize` invocations covering `invocations`.
inline uint32_t groupCount(uint64_t invocations, uint32_t groupSize) {
  return static_cast<uint32_t>((invocations + groupSize - 1) / groupSize);
}

}  // namespace lava::detail
