#include "buffer.h"

#include <algorithm>

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

Buffer::Buffer(const Context& context, void* host, VkDeviceSize size, VkBufferUsageFlags usage)
    : size_(size) {
  VkDevice device = context.device();
  constexpr auto kHandle = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT;
  VkExternalMemoryBufferCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO};
  external.handleTypes = kHandle;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.pNext = &external;
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBuffer(device, &info, nullptr, &buffer));
  buffer_ = UniqueBuffer(device, buffer);

  auto hostPointerProperties = reinterpret_cast<PFN_vkGetMemoryHostPointerPropertiesEXT>(
      vkGetDeviceProcAddr(device, "vkGetMemoryHostPointerPropertiesEXT"));
  if (!hostPointerProperties) throw ResourceError("VK_EXT_external_memory_host is not enabled");
  VkMemoryHostPointerPropertiesEXT pointer{VK_STRUCTURE_TYPE_MEMORY_HOST_POINTER_PROPERTIES_EXT};
  VK_CHECK(hostPointerProperties(device, kHandle, host, &pointer));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device, buffer, &requirements);
  VkImportMemoryHostPointerInfoEXT import{VK_STRUCTURE_TYPE_IMPORT_MEMORY_HOST_POINTER_INFO_EXT};
  import.handleType = kHandle;
  import.pHostPointer = host;
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.pNext = &import;
  const VkDeviceSize alignment = std::max<VkDeviceSize>(context.hostImportAlignment(), 1);
  alloc.allocationSize =
      (std::max(size, requirements.size) + alignment - 1) / alignment * alignment;
  alloc.memoryTypeIndex = context.findMemoryType(
      requirements.memoryTypeBits & pointer.memoryTypeBits,
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkDeviceMemory raw = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &raw));
  memory_ = UniqueMemory(device, raw);
  VK_CHECK(vkBindBufferMemory(device, buffer, raw, 0));
  mapped_ = host;
}

// Freeing the memory unmaps it; members then release buffer before memory.
Buffer::~Buffer() = default;

}  // namespace lava
