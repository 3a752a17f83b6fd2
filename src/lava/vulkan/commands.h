// Descriptors and barriers as Lava records them: push descriptors where the device offers
// them (no pools, no sets: each consumer pushes the buffers it reads), else sets written
// from a per-frame-slot arena; and one helper per barrier kind. Callers name the hazard of
// each barrier in a comment.
#pragma once
#include <array>
#include <initializer_list>
#include <unordered_map>
#include <vector>

#include "device_context.h"
#include "unique.h"
#include "internal.h"

namespace lava::detail {

// A set layout for Descriptors::bind (a push-descriptor layout where the device has push
// descriptors): binding b of types[b], each visible to `stages`; combined image samplers
// use `sampler` (immutable) when it is given.
LAVA_INTERNAL UniqueDescriptorSetLayout createSetLayout(const DeviceContext& context,
                                          std::initializer_list<VkDescriptorType> types,
                                          VkShaderStageFlags stages,
                                          VkSampler sampler = VK_NULL_HANDLE);
// A sampler clamping to the edge, with `filter` for both magnification and minification.
UniqueSampler createSampler(const DeviceContext& context, VkFilter filter);
// One set layout (or none) and one push-constant range of `pushBytes` for `pushStages`.
LAVA_INTERNAL UniquePipelineLayout createPipelineLayout(const DeviceContext& context, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes);

// Descriptor sets for a device without push descriptors, one arena per frame slot: each
// bind takes the next set of its layout and writes it afresh. Sets are allocated from the
// arena's own pools the first time a slot needs that many and kept; reset() makes them
// available again once the work recorded with them has finished (a command buffer recorded
// with them cannot be submitted again after that). Empty where push descriptors are used.
class LAVA_INTERNAL DescriptorArena {
 public:
  DescriptorArena() = default;
  explicit DescriptorArena(const DeviceContext& context) : c_(&context) {}
  DescriptorArena(DescriptorArena&&) noexcept = default;
  DescriptorArena& operator=(DescriptorArena&&) noexcept = default;
  void reset();
  VkDescriptorSet take(VkDescriptorSetLayout layout);

 private:
  struct Sets {
    std::vector<VkDescriptorSet> sets;
    size_t used = 0;
  };
  const DeviceContext* c_ = nullptr;
  std::vector<UniqueDescriptorPool> pools_;  // destroying a pool frees its sets
  std::unordered_map<VkDescriptorSetLayout, Sets> byLayout_;
};

// Up to eight descriptor writes, bound at once: pushed, or written into a set of `arena`.
class LAVA_INTERNAL Descriptors {
 public:
  Descriptors& buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                      VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE);
  Descriptors& texels(uint32_t binding, VkBufferView view);
  Descriptors& image(uint32_t binding, VkDescriptorType type, VkImageView view,
                     VkImageLayout layout, VkSampler sampler = VK_NULL_HANDLE);
  // Binds the writes as set 0 of `layout`, whose set layout is `setLayout`.
  void bind(const DeviceContext& context, VkCommandBuffer commands, VkPipelineBindPoint point,
            VkPipelineLayout layout, VkDescriptorSetLayout setLayout, DescriptorArena& arena) const;

 private:
  static constexpr size_t kMax = 8;
  std::array<VkWriteDescriptorSet, kMax> writes_{};
  std::array<VkDescriptorBufferInfo, kMax> buffers_{};
  std::array<VkDescriptorImageInfo, kMax> images_{};
  std::array<VkBufferView, kMax> views_{};
  size_t count_ = 0;
  // Appends a write of `info` (stored in `infos`, pointed at by the write's `field`).
  template <typename Info>
  Descriptors& add(uint32_t binding, VkDescriptorType type, std::array<Info, kMax>& infos,
                   const Info* VkWriteDescriptorSet::*field, const Info& info);
};

// One global memory barrier.
LAVA_INTERNAL void memoryBarrier(const DeviceContext& context, VkCommandBuffer commands,
                   VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);
// Compute reads and writes after every earlier write (compute, transfer) and read (draws,
// copies) of the same buffers.
void beforeCompute(const DeviceContext& context, VkCommandBuffer commands);
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
