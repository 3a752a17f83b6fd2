// What the library (through a device's function table) and the program (through the loader)
// both write, written once: pipeline barriers (`barrier` is the vkCmdPipelineBarrier to
// call), the one kind of image view both create, and the error of an allocation that ran
// out of memory.
#pragma once
#include <vulkan/vulkan.h>

#include <string>

#include "lava/error.h"

namespace lava::common {

// One global memory barrier.
inline void memoryBarrier(PFN_vkCmdPipelineBarrier barrier, VkCommandBuffer commands,
                          VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                          VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  const VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, srcAccess, dstAccess};
  barrier(commands, srcStage, dstStage, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

// One image barrier over the single mip and layer of `image`, with a layout change.
inline void imageBarrier(PFN_vkCmdPipelineBarrier barrier, VkCommandBuffer commands, VkImage image,
                         VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                         VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                         VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  VkImageMemoryBarrier layout{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  layout.srcAccessMask = srcAccess;
  layout.dstAccessMask = dstAccess;
  layout.oldLayout = from;
  layout.newLayout = to;
  layout.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  layout.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  layout.image = image;
  layout.subresourceRange = {aspect, 0, 1, 0, 1};
  barrier(commands, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &layout);
}

// A 2D view of `aspect` over the single mip and layer of `image` (an imageInfo2D image).
inline VkImageViewCreateInfo viewInfo2D(VkImage image, VkFormat format, VkImageAspectFlags aspect) {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image;
  info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  info.format = format;
  info.subresourceRange = {aspect, 0, 1, 0, 1};
  return info;
}

// ResourceError naming the size when vkAllocateMemory of `size` bytes returned `result` for
// want of memory: a user can act on the size, not on the bare VkResult VK_CHECK reports.
inline void throwIfOutOfMemory(VkResult result, VkDeviceSize size) {
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
    throw ResourceError("out of memory: vkAllocateMemory of " +
                        (size >= (VkDeviceSize{1} << 20) ? std::to_string(size >> 20) + " MiB"
                                                         : std::to_string(size) + " bytes") +
                        " on the Vulkan device failed with " + resultName(result));
}

}  // namespace lava::common
