// Pipeline barriers, written once for the library (through a device's function table) and
// the program (through the loader): `barrier` is the vkCmdPipelineBarrier to call.
#pragma once
#include <vulkan/vulkan.h>

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

}  // namespace lava::common
