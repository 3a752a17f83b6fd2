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
