#include "descriptors.h"

#include <vector>

#include "vk_check.h"

namespace lava {

UniqueDescriptorSetLayout createStorageSetLayout(VkDevice device, uint32_t count,
                                                 VkShaderStageFlags stages) {
  return createSetLayout(
      device, std::vector<VkDescriptorType>(count, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), stages);
}

UniqueDescriptorSetLayout createSetLayout(VkDevice device,
                                          const std::vector<VkDescriptorType>& types,
                                          VkShaderStageFlags stages) {
  const uint32_t count = static_cast<uint32_t>(types.size());
  std::vector<VkDescriptorSetLayoutBinding> bindings(count);
  for (uint32_t b = 0; b < count; ++b) bindings[b] = {b, types[b], 1, stages, nullptr};
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.bindingCount = count;
  info.pBindings = bindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, &layout));
  return UniqueDescriptorSetLayout(device, layout);
}

UniquePipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set,
                                          VkShaderStageFlags pushStages, uint32_t pushBytes) {
  VkPushConstantRange push{pushStages, 0, pushBytes};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = 1;
  info.pSetLayouts = &set;
  info.pushConstantRangeCount = 1;
  info.pPushConstantRanges = &push;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreatePipelineLayout(device, &info, nullptr, &layout));
  return UniquePipelineLayout(device, layout);
}

UniqueDescriptorPool createStoragePool(VkDevice device, uint32_t sets, uint32_t descriptors) {
  return createPool(device, sets, {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, descriptors}});
}

UniqueDescriptorPool createPool(VkDevice device, uint32_t sets,
                                const std::vector<VkDescriptorPoolSize>& sizes) {
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = sets;
  info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  info.pPoolSizes = sizes.data();
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorPool(device, &info, nullptr, &pool));
  return UniqueDescriptorPool(device, pool);
}

VkDescriptorSet allocateSet(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout) {
  VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  info.descriptorPool = pool;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateDescriptorSets(device, &info, &set));
  return set;
}

namespace {

// A write of the one descriptor at `binding`; the caller points it at its buffer or view.
VkWriteDescriptorSet oneDescriptor(VkDescriptorSet set, uint32_t binding, VkDescriptorType type) {
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = type;
  return write;
}

}  // namespace

void writeStorage(VkDevice device, VkDescriptorSet set, uint32_t binding,
                  const VkDescriptorBufferInfo& range) {
  VkWriteDescriptorSet write = oneDescriptor(set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  write.pBufferInfo = &range;
  vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
}

UniqueBufferView createTexelView(VkDevice device, VkBuffer buffer, VkDeviceSize range) {
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer;
  info.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  info.offset = 0;
  info.range = range;
  VkBufferView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBufferView(device, &info, nullptr, &view));
  return UniqueBufferView(device, view);
}

void writeTexels(VkDevice device, VkDescriptorSet set, uint32_t binding, VkBufferView view) {
  VkWriteDescriptorSet write =
      oneDescriptor(set, binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  write.pTexelBufferView = &view;
  vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
}

void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = srcAccess;
  memory.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(commands, srcStage, dstStage, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

void imageBarrier(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, 1, 0, 1};
  vkCmdPipelineBarrier(commands, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

}  // namespace lava
