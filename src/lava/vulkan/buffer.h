// A VkBuffer with memory of its own: device-local for particles, host-visible and mapped
// for uploads (the schedule, the scene) and read-backs (cached where the device has it).
#pragma once
#include <utility>

#include "device_context.h"
#include "unique.h"
#include "internal.h"

namespace lava::detail {

enum class MemoryUse {
  Device,    // device-local, not mapped
  Upload,    // host-visible, mapped; the host writes, the device reads
  Readback,  // host-visible, mapped, cached where offered; the device writes, the host reads
};

class LAVA_INTERNAL Buffer {
 public:
  Buffer() = default;
  Buffer(const DeviceContext& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
  // A moved-from buffer is empty: no handle, no memory, mapped() null.
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept {
    context_ = other.context_;
    size_ = std::exchange(other.size_, 0);
    coherent_ = std::exchange(other.coherent_, true);
    // The memory outlives its mapping: release the handles in creation order's reverse.
    buffer_ = std::move(other.buffer_);
    memory_ = std::move(other.memory_);
    mapped_ = std::exchange(other.mapped_, nullptr);
    return *this;
  }

  VkBuffer get() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // null for MemoryUse::Device
  // After host writes / before host reads of mapped memory that is not coherent.
  void flush() const;
  void invalidate() const;

 private:
  const DeviceContext* context_ = nullptr;
  VkDeviceSize size_ = 0;
  bool coherent_ = true;
  UniqueBuffer buffer_;
  UniqueMemory memory_;
  void* mapped_ = nullptr;
};

// A device-local 2D image, one mip and layer, with a view of `aspect`.
struct Image {
  UniqueImage image;
  UniqueMemory memory;
  UniqueImageView view;
  VkExtent2D extent{0, 0};
  VkFormat format = VK_FORMAT_UNDEFINED;
};
Image createImage(const DeviceContext& context, VkExtent2D extent, VkFormat format,
                  VkImageUsageFlags usage, VkImageAspectFlags aspect);

// Allocates `size` bytes of memory type `type` (throws ResourceError, naming the size,
// when the device is out of memory).
UniqueMemory allocateMemory(const DeviceContext& context, VkDeviceSize size, uint32_t type);

// A view of `range` bytes of `buffer` as texels of `format` (a uniform texel buffer).
LAVA_INTERNAL UniqueBufferView createTexelView(const DeviceContext& context, VkBuffer buffer, VkDeviceSize range,
                                 VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT);

}  // namespace lava::detail
