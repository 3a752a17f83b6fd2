// The library's owned handles: common::Unique destroyed through the device's function table
// with the host's allocation callbacks.
#pragma once
#include <vulkan/vulkan.h>

#include <utility>

#include "common/unique.h"
#include "device_context.h"

namespace lava::detail {

using common::DestroyFn;
using common::Unique;

inline DestroyFn<VkBuffer> destroyFn(const Vk& vk, VkBuffer) {
  return vk.DestroyBuffer;
}
inline DestroyFn<VkBufferView> destroyFn(const Vk& vk, VkBufferView) {
  return vk.DestroyBufferView;
}
inline DestroyFn<VkDeviceMemory> destroyFn(const Vk& vk, VkDeviceMemory) {
  return vk.FreeMemory;
}
inline DestroyFn<VkImage> destroyFn(const Vk& vk, VkImage) {
  return vk.DestroyImage;
}
inline DestroyFn<VkImageView> destroyFn(const Vk& vk, VkImageView) {
  return vk.DestroyImageView;
}
inline DestroyFn<VkSampler> destroyFn(const Vk& vk, VkSampler) {
  return vk.DestroySampler;
}
inline DestroyFn<VkShaderModule> destroyFn(const Vk& vk, VkShaderModule) {
  return vk.DestroyShaderModule;
}
inline DestroyFn<VkDescriptorSetLayout> destroyFn(const Vk& vk, VkDescriptorSetLayout) {
  return vk.DestroyDescriptorSetLayout;
}
inline DestroyFn<VkDescriptorPool> destroyFn(const Vk& vk, VkDescriptorPool) {
  return vk.DestroyDescriptorPool;
}
inline DestroyFn<VkPipelineLayout> destroyFn(const Vk& vk, VkPipelineLayout) {
  return vk.DestroyPipelineLayout;
}
inline DestroyFn<VkPipeline> destroyFn(const Vk& vk, VkPipeline) {
  return vk.DestroyPipeline;
}
inline DestroyFn<VkRenderPass> destroyFn(const Vk& vk, VkRenderPass) {
  return vk.DestroyRenderPass;
}
inline DestroyFn<VkFramebuffer> destroyFn(const Vk& vk, VkFramebuffer) {
  return vk.DestroyFramebuffer;
}
inline DestroyFn<VkCommandPool> destroyFn(const Vk& vk, VkCommandPool) {
  return vk.DestroyCommandPool;
}
inline DestroyFn<VkFence> destroyFn(const Vk& vk, VkFence) {
  return vk.DestroyFence;
}
inline DestroyFn<VkQueryPool> destroyFn(const Vk& vk, VkQueryPool) {
  return vk.DestroyQueryPool;
}

using UniqueBuffer = Unique<VkBuffer>;
using UniqueBufferView = Unique<VkBufferView>;
using UniqueMemory = Unique<VkDeviceMemory>;
using UniqueImage = Unique<VkImage>;
using UniqueImageView = Unique<VkImageView>;
using UniqueSampler = Unique<VkSampler>;
using UniqueShaderModule = Unique<VkShaderModule>;
using UniqueDescriptorSetLayout = Unique<VkDescriptorSetLayout>;
using UniqueDescriptorPool = Unique<VkDescriptorPool>;
using UniquePipelineLayout = Unique<VkPipelineLayout>;
using UniquePipeline = Unique<VkPipeline>;
using UniqueRenderPass = Unique<VkRenderPass>;
using UniqueFramebuffer = Unique<VkFramebuffer>;
using UniqueCommandPool = Unique<VkCommandPool>;
using UniqueFence = Unique<VkFence>;
using UniqueQueryPool = Unique<VkQueryPool>;

}  // namespace lava::detail
