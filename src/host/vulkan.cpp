#include "vulkan.h"

#include <string>

#include "common/barriers.h"
#include "common/images.h"

namespace lava::host {

uint32_t memoryType(const Device& device, uint32_t typeBits, VkMemoryPropertyFlags required,
                    VkMemoryPropertyFlags preferred) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device.handles().physicalDevice, &memory);
  for (VkMemoryPropertyFlags wanted : {required | preferred, required})
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
      if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted)
        return i;
  throw ResourceError("no Vulkan memory type with the needed properties on this device");
}

bool coherent(const Device& device, uint32_t type) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device.handles().physicalDevice, &memory);
  return memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
}

OwnedMemory allocate(const Device& device, VkDeviceSize size, uint32_t type, const void* next) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.pNext = next;
  info.allocationSize = size;
  info.memoryTypeIndex = type;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  const VkResult result = vkAllocateMemory(device.handles().device, &info, nullptr, &memory);
  common::throwIfOutOfMemory(result, size);
  VK_CHECK(result);
  return OwnedMemory(device.handles().device, memory);
}

OwnedImageView createView(const Device& device, VkImage image, VkFormat format,
                          VkImageAspectFlags aspect) {
  const VkImageViewCreateInfo info = common::viewInfo2D(image, format, aspect);
  VkImageView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImageView(device.handles().device, &info, nullptr, &view));
  return OwnedImageView(device.handles().device, view);
}

ReadbackBuffer::ReadbackBuffer(const Device& device, VkDeviceSize size)
    : device_(device.handles().device) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer));
  buffer_ = OwnedBuffer(device_, buffer);
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device_, buffer, &requirements);
  const uint32_t type =
      memoryType(device, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                 VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  memory_ = allocate(device, requirements.size, type);
  coherent_ = coherent(device, type);
  VK_CHECK(vkBindBufferMemory(device_, buffer, memory_, 0));
  VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

void ReadbackBuffer::recordCopy(VkCommandBuffer commands, VkImage image, VkExtent2D extent) const {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(commands, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer_, 1,
                         &region);
  // RAW: the host reads what the copy wrote.
  memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

const void* ReadbackBuffer::read() const {
  if (!coherent_) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0,
                              VK_WHOLE_SIZE};
    VK_CHECK(vkInvalidateMappedMemoryRanges(device_, 1, &range));
  }
  return mapped_;
}

Image createImage(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect) {
  VkDevice handle = device.handles().device;
  const VkImageCreateInfo info = common::imageInfo2D(extent, format, usage);
  Image out;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImage(handle, &info, nullptr, &image));
  out.image = OwnedImage(handle, image);
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(handle, image, &requirements);
  out.memory = allocate(
      device, requirements.size,
      memoryType(device, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT));
  VK_CHECK(vkBindImageMemory(handle, image, out.memory, 0));
  out.view = createView(device, image, format, aspect);
  return out;
}

VkImageUsageFlags copyTargetUsage(const Device& device, VkFormat format) {
  VkFormatProperties properties;
  vkGetPhysicalDeviceFormatProperties(device.handles().physicalDevice, format, &properties);
  return (properties.optimalTilingFeatures & VK_FORMAT_FEATURE_TRANSFER_DST_BIT)
             ? VK_IMAGE_USAGE_TRANSFER_DST_BIT
             : 0;
}

void imageBarrier(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  common::imageBarrier(vkCmdPipelineBarrier, commands, image, aspect, from, to, srcStage,
                       srcAccess, dstStage, dstAccess);
}

void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  common::memoryBarrier(vkCmdPipelineBarrier, commands, srcStage, srcAccess, dstStage, dstAccess);
}

bool applyDeviceProfile(DeviceOptions& options, const std::string& profile) {
  if (profile.empty() || profile == "full") return true;
  if (profile != "minimal") return false;
  options.pushDescriptors = false;
  options.int64Atomics = false;
  options.floatControls = false;
  return true;
}

}  // namespace lava::host
