#include "commands.h"

#include <stdexcept>
#include <vector>

#include "common/barriers.h"
#include "common/check.h"

namespace lava::detail {

UniqueDescriptorSetLayout createSetLayout(const DeviceContext& c,
                                          std::initializer_list<VkDescriptorType> types,
                                          VkShaderStageFlags stages, VkSampler sampler) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (VkDescriptorType type : types)
    bindings.push_back(
        {static_cast<uint32_t>(bindings.size()), type, 1, stages,
         type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER && sampler ? &sampler : nullptr});
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  if (c.pushDescriptors) info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  info.bindingCount = static_cast<uint32_t>(bindings.size());
  info.pBindings = bindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateDescriptorSetLayout(c.device(), &info, c.allocator(), &layout));
  return UniqueDescriptorSetLayout(c, layout);
}

UniqueSampler createSampler(const DeviceContext& c, VkFilter filter) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = filter;
  info.minFilter = filter;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler sampler = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateSampler(c.device(), &info, c.allocator(), &sampler));
  return UniqueSampler(c, sampler);
}

UniquePipelineLayout createPipelineLayout(const DeviceContext& c, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes) {
  VkPushConstantRange range{pushStages, 0, pushBytes};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = set ? 1 : 0;
  info.pSetLayouts = &set;
  info.pushConstantRangeCount = pushBytes ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreatePipelineLayout(c.device(), &info, c.allocator(), &layout));
  return UniquePipelineLayout(c, layout);
}

// Every kind of write keeps its info at the write's own index, where the pointer the write
// holds stays valid until bind; the limit is checked before anything is stored.
template <typename Info>
Descriptors& Descriptors::add(uint32_t binding, VkDescriptorType type,
                              std::array<Info, kMax>& infos,
                              const Info* VkWriteDescriptorSet::*field, const Info& info) {
  if (count_ == kMax) throw std::logic_error("Descriptors: too many writes");
  VkWriteDescriptorSet& w = writes_[count_];
  w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  infos[count_] = info;
  w.*field = &infos[count_];
  ++count_;
  return *this;
}

Descriptors& Descriptors::buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                                 VkDeviceSize offset, VkDeviceSize range) {
  return add(binding, type, buffers_, &VkWriteDescriptorSet::pBufferInfo, {buffer, offset, range});
}

Descriptors& Descriptors::texels(uint32_t binding, VkBufferView view) {
  return add(binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, views_,
             &VkWriteDescriptorSet::pTexelBufferView, view);
}

Descriptors& Descriptors::image(uint32_t binding, VkDescriptorType type, VkImageView view,
                                VkImageLayout layout, VkSampler sampler) {
  return add(binding, type, images_, &VkWriteDescriptorSet::pImageInfo, {sampler, view, layout});
}

void Descriptors::bind(const DeviceContext& c, VkCommandBuffer commands, VkPipelineBindPoint point,
                       VkPipelineLayout layout, VkDescriptorSetLayout setLayout,
                       DescriptorArena& arena) const {
  if (c.pushDescriptors) {
    c.vk.CmdPushDescriptorSetKHR(commands, point, layout, 0, static_cast<uint32_t>(count_),
                                 writes_.data());
    return;
  }
  // Written afresh every time: a handle equal to the set's last one may name a new object.
  const VkDescriptorSet set = arena.take(setLayout);
  std::array<VkWriteDescriptorSet, kMax> writes = writes_;
  for (size_t i = 0; i < count_; ++i) writes[i].dstSet = set;
  c.vk.UpdateDescriptorSets(c.device(), static_cast<uint32_t>(count_), writes.data(), 0, nullptr);
  c.vk.CmdBindDescriptorSets(commands, point, layout, 0, 1, &set, 0, nullptr);
}

void DescriptorArena::reset() {
  for (auto& entry : byLayout_) entry.second.used = 0;
}

VkDescriptorSet DescriptorArena::take(VkDescriptorSetLayout layout) {
  Sets& sets = byLayout_[layout];
  if (sets.used < sets.sets.size()) return sets.sets[sets.used++];
  // Every layout Lava makes has at most eight bindings of these types.
  constexpr uint32_t kSetsPerPool = 32;
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VkResult result = VK_ERROR_OUT_OF_POOL_MEMORY;
  if (!pools_.empty()) {
    alloc.descriptorPool = pools_.back();
    result = c_->vk.AllocateDescriptorSets(c_->device(), &alloc, &set);
  }
  if (result == VK_ERROR_OUT_OF_POOL_MEMORY || result == VK_ERROR_FRAGMENTED_POOL) {
    const std::array<VkDescriptorPoolSize, 5> sizes{{
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 8 * kSetsPerPool},
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 8 * kSetsPerPool},
        {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 8 * kSetsPerPool},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8 * kSetsPerPool},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 8 * kSetsPerPool},  // the molten surface's
    }};
    VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    info.maxSets = kSetsPerPool;
    info.poolSizeCount = static_cast<uint32_t>(sizes.size());
    info.pPoolSizes = sizes.data();
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VK_CHECK(c_->vk.CreateDescriptorPool(c_->device(), &info, c_->allocator(), &pool));
    pools_.emplace_back(*c_, pool);
    alloc.descriptorPool = pool;
    result = c_->vk.AllocateDescriptorSets(c_->device(), &alloc, &set);
  }
  VK_CHECK_RESULT(result, "vkAllocateDescriptorSets");
  sets.sets.push_back(set);
  return sets.sets[sets.used++];
}

void memoryBarrier(const DeviceContext& c, VkCommandBuffer commands, VkPipelineStageFlags srcStage,
                   VkAccessFlags srcAccess, VkPipelineStageFlags dstStage,
                   VkAccessFlags dstAccess) {
  common::memoryBarrier(c.vk.CmdPipelineBarrier, commands, srcStage, srcAccess, dstStage,
                        dstAccess);
}

void imageBarrier(const DeviceContext& c, VkCommandBuffer commands, VkImage image,
                  VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                  VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  common::imageBarrier(c.vk.CmdPipelineBarrier, commands, image, aspect, from, to, srcStage,
                       srcAccess, dstStage, dstAccess);
}

void beforeCompute(const DeviceContext& c, VkCommandBuffer commands) {
  memoryBarrier(c, commands,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                    VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace lava::detail
