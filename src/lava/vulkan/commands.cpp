#include "commands.h"

#include <stdexcept>
#include <vector>

#include "check.h"

namespace lava::detail {

UniqueDescriptorSetLayout createPushLayout(const DeviceContext& c,
                                           std::initializer_list<VkDescriptorType> types,
                                           VkShaderStageFlags stages, VkSampler sampler) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (VkDescriptorType type : types)
    bindings.push_back({static_cast<uint32_t>(bindings.size()), type, 1, stages,
                        type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER && sampler ? &sampler
                                                                                    : nullptr});
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
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

VkWriteDescriptorSet& PushDescriptors::next(uint32_t binding, VkDescriptorType type) {
  if (count_ == kMax) throw std::logic_error("PushDescriptors: too many writes");
  VkWriteDescriptorSet& w = writes_[count_];
  w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  return w;
}

PushDescriptors& PushDescriptors::buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                                         VkDeviceSize offset, VkDeviceSize range) {
  buffers_[count_] = {buffer, offset, range};
  next(binding, type).pBufferInfo = &buffers_[count_];
  ++count_;
  return *this;
}

PushDescriptors& PushDescriptors::texels(uint32_t binding, VkBufferView view) {
  views_[count_] = view;
  next(binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER).pTexelBufferView = &views_[count_];
  ++count_;
  return *this;
}

PushDescriptors& PushDescriptors::image(uint32_t binding, VkDescriptorType type, VkImageView view,
                                        VkImageLayout layout, VkSampler sampler) {
  images_[count_] = {sampler, view, layout};
  next(binding, type).pImageInfo = &images_[count_];
  ++count_;
  return *this;
}

void PushDescriptors::push(const DeviceContext& c, VkCommandBuffer commands,
                           VkPipelineBindPoint point, VkPipelineLayout layout) const {
  c.vk.CmdPushDescriptorSetKHR(commands, point, layout, 0, static_cast<uint32_t>(count_),
                               writes_.data());
}

void memoryBarrier(const DeviceContext& c, VkCommandBuffer commands, VkPipelineStageFlags srcStage,
                   VkAccessFlags srcAccess, VkPipelineStageFlags dstStage,
                   VkAccessFlags dstAccess) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, srcAccess, dstAccess};
  c.vk.CmdPipelineBarrier(commands, srcStage, dstStage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void imageBarrier(const DeviceContext& c, VkCommandBuffer commands, VkImage image,
                  VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                  VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, 1, 0, 1};
  c.vk.CmdPipelineBarrier(commands, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

}  // namespace lava::detail
