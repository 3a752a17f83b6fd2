// A VkBuffer with its own memory: device-local for particles, host-visible (and mapped)
// for staging and the emission schedule.
#pragma once
#include "context.h"

namespace lava {

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
         VkMemoryPropertyFlags memory);
  // A host-visible buffer over `size` bytes of the caller's memory at `host`, used in place
  // (VK_EXT_external_memory_host; both aligned to Context::hostImportAlignment()). The
  // memory must outlive the buffer.
  Buffer(const Context& context, void* host, VkDeviceSize size, VkBufferUsageFlags usage);
  Buffer(Buffer&&) = default;
  Buffer& operator=(Buffer&&) = default;
  ~Buffer();

  VkBuffer get() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // null unless host-visible

 private:
  VkDeviceSize size_ = 0;
  UniqueBuffer buffer_;
  UniqueMemory memory_;
  void* mapped_ = nullptr;
};

}  // namespace lava
