#include "buffer.h"

#include "vk_check.h"

namespace lava {

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
               VkMemoryPropertyFlags memory)
    : size_(size) {
  VkDevice device = context.device();
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBuffer(device, &info, nullptr, &buffer));
  buffer_ = UniqueBuffer(device, buffer);

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device, buffer, &requirements);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = requirements.size;
  alloc.memoryTypeIndex = context.findMemoryType(requirements.memoryTypeBits, memory);
  VkDeviceMemory raw = VK_NULL_HANDLE;
  VkResult allocated = vkAllocateMemory(device, &alloc, nullptr, &raw);
  if (allocated == VK_ERROR_OUT_OF_DEVICE_MEMORY || allocated == VK_ERROR_OUT_OF_HOST_MEMORY)
    throw ResourceError("out of memory allocating " + std::to_string(size >> 20) +
                        " MiB on the Vulkan device");
  VK_CHECK(allocated);
  memory_ = UniqueMemory(device, raw);
  VK_CHECK(vkBindBufferMemory(device, buffer, raw, 0));
  if (memory & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
    VK_CHECK(vkMapMemory(device, raw, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

// Freeing the memory unmaps it; members then release buffer before memory.
Buffer::~Buffer() = default;

}  // namespace lava
