#include "buffer.h"

#include "common/barriers.h"
#include "common/check.h"
#include "common/images.h"

namespace lava::detail {

UniqueMemory allocateMemory(const DeviceContext& c, VkDeviceSize size, uint32_t type) {
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = size;
  alloc.memoryTypeIndex = type;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  const VkResult allocated = c.vk.AllocateMemory(c.device(), &alloc, c.allocator(), &memory);
  common::throwIfOutOfMemory(allocated, size);
  VK_CHECK_RESULT(allocated, "vkAllocateMemory");
  return UniqueMemory(c, memory);
}

Buffer::Buffer(const DeviceContext& c, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use)
    : context_(&c), size_(size) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateBuffer(c.device(), &info, c.allocator(), &buffer));
  buffer_ = UniqueBuffer(c, buffer);

  VkMemoryRequirements requirements;
  c.vk.GetBufferMemoryRequirements(c.device(), buffer, &requirements);
  VkMemoryPropertyFlags required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, preferred = 0;
  if (use == MemoryUse::Upload) {
    required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    preferred = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  } else if (use == MemoryUse::Readback) {
    required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  }
  const uint32_t type = c.findMemoryType(requirements.memoryTypeBits, required, preferred);
  coherent_ = c.memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  memory_ = allocateMemory(c, requirements.size, type);
  VK_CHECK(c.vk.BindBufferMemory(c.device(), buffer, memory_, 0));
  if (use != MemoryUse::Device)
    VK_CHECK(c.vk.MapMemory(c.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

void Buffer::flush() const {
  if (coherent_ || !mapped_) return;
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0,
                            VK_WHOLE_SIZE};
  VK_CHECK(context_->vk.FlushMappedMemoryRanges(context_->device(), 1, &range));
}

void Buffer::invalidate() const {
  if (coherent_ || !mapped_) return;
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0,
                            VK_WHOLE_SIZE};
  VK_CHECK(context_->vk.InvalidateMappedMemoryRanges(context_->device(), 1, &range));
}

Image createImage(const DeviceContext& c, VkExtent2D extent, VkFormat format,
                  VkImageUsageFlags usage, VkImageAspectFlags aspect) {
  const VkImageCreateInfo info = common::imageInfo2D(extent, format, usage);
  Image out;
  out.extent = extent;
  out.format = format;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateImage(c.device(), &info, c.allocator(), &image));
  out.image = UniqueImage(c, image);
  VkMemoryRequirements requirements;
  c.vk.GetImageMemoryRequirements(c.device(), image, &requirements);
  out.memory = allocateMemory(
      c, requirements.size,
      c.findMemoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT));
  VK_CHECK(c.vk.BindImageMemory(c.device(), image, out.memory, 0));
  const VkImageViewCreateInfo view = common::viewInfo2D(image, format, aspect);
  VkImageView handle = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateImageView(c.device(), &view, c.allocator(), &handle));
  out.view = UniqueImageView(c, handle);
  return out;
}

UniqueBufferView createTexelView(const DeviceContext& c, VkBuffer buffer, VkDeviceSize range,
                                 VkFormat format) {
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer;
  info.format = format;
  info.range = range;
  VkBufferView view = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateBufferView(c.device(), &info, c.allocator(), &view));
  return UniqueBufferView(c, view);
}

}  // namespace lava::detail
