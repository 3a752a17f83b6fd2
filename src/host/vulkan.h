// What the `lava` program needs of Vulkan beyond Lava's API, as a host application would
// write it: checked calls, owned handles, device-local images, one-shot submissions. It
// calls the Vulkan loader's functions, Lava's public API, and the pieces in src/common.
#pragma once
#include <vulkan/vulkan.h>

#include <string>
#include <utility>

#include "common/check.h"
#include "common/unique.h"
#include "lava/device.h"
#include "lava/error.h"

namespace lava::host {

// One device-level handle, destroyed with the loader's `Destroy` (vkDestroy* or vkFreeMemory).
template <typename T, common::DestroyFn<T> Destroy>
class Owned : public common::Unique<T> {
 public:
  Owned() = default;
  Owned(VkDevice device, T handle) : common::Unique<T>(device, nullptr, Destroy, handle) {}
};

using OwnedImage = Owned<VkImage, vkDestroyImage>;
using OwnedImageView = Owned<VkImageView, vkDestroyImageView>;
using OwnedMemory = Owned<VkDeviceMemory, vkFreeMemory>;
using OwnedBuffer = Owned<VkBuffer, vkDestroyBuffer>;
using OwnedFence = Owned<VkFence, vkDestroyFence>;
using OwnedSemaphore = Owned<VkSemaphore, vkDestroySemaphore>;
using OwnedCommandPool = Owned<VkCommandPool, vkDestroyCommandPool>;
using OwnedQueryPool = Owned<VkQueryPool, vkDestroyQueryPool>;
using OwnedRenderPass = Owned<VkRenderPass, vkDestroyRenderPass>;
using OwnedFramebuffer = Owned<VkFramebuffer, vkDestroyFramebuffer>;
using OwnedDescriptorPool = Owned<VkDescriptorPool, vkDestroyDescriptorPool>;

// A memory type of `device` among `typeBits` with `required`, one that also has
// `preferred` if any does (ResourceError when none has `required`).
uint32_t memoryType(const Device& device, uint32_t typeBits, VkMemoryPropertyFlags required,
                    VkMemoryPropertyFlags preferred = 0);
// Allocates `size` bytes of memory type `type`; out of memory is a ResourceError naming
// the size.
OwnedMemory allocate(const Device& device, VkDeviceSize size, uint32_t type,
                     const void* next = nullptr);
// Whether memory type `type` is host-coherent.
bool coherent(const Device& device, uint32_t type);

struct Image {
  OwnedImage image;
  OwnedMemory memory;
  OwnedImageView view;
};
// A device-local 2D image (one mip, one layer, optimal tiling) and a view of `aspect`.
Image createImage(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect);
OwnedImageView createView(const Device& device, VkImage image, VkFormat format,
                          VkImageAspectFlags aspect);
// TRANSFER_DST when `format` accepts copies into optimal-tiling images on this device.
VkImageUsageFlags copyTargetUsage(const Device& device, VkFormat format);

void imageBarrier(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);
void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

// A buffer the device copies into (TRANSFER_DST) and the host reads, mapped for its whole
// life; in cached memory where the device has it. Empty when default-constructed.
class ReadbackBuffer {
 public:
  ReadbackBuffer() = default;
  ReadbackBuffer(const Device& device, VkDeviceSize size);
  VkBuffer buffer() const { return buffer_; }
  // Records the copy of `image`'s colour (TRANSFER_SRC_OPTIMAL, `extent`) into the buffer and
  // makes it available to the host.
  void recordCopy(VkCommandBuffer commands, VkImage image, VkExtent2D extent) const;
  // What the device wrote, once the host has waited for it (invalidated when not coherent).
  const void* read() const;

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  OwnedBuffer buffer_;
  OwnedMemory memory_;
  void* mapped_ = nullptr;
  bool coherent_ = true;
};

// A device profile by name: "full" (or empty: every optional path the device offers) or
// "minimal" (none: descriptor sets instead of push descriptors, 32-bit atomics, no
// float-control declarations), as a device that lacks them runs. False for another name.
bool applyDeviceProfile(DeviceOptions& options, const std::string& profile);
constexpr const char* kDeviceProfiles = "full or minimal";

}  // namespace lava::host
