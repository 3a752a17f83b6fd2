// A render target with no window: a color and a depth image, and a host-visible buffer the
// color image is copied into for reading back; or, for MIT-SHM, a linear color image over
// memory the caller owns, which the host reads in place.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "lava/device.h"
#include "vulkan.h"

namespace lava::host {

// Copies `height` rows of `row` bytes from tightly packed `source` into `destination`, whose
// rows start `pitch` bytes apart (pitch >= row, as an X server may pad them); the padding
// is left as it was.
void copyRows(uint8_t* destination, size_t pitch, const uint8_t* source, size_t row,
              uint32_t height);

// Where FrameRenderer draws one frame.
struct FrameTarget {
  VkImage color = VK_NULL_HANDLE;
  VkImageView colorView = VK_NULL_HANDLE;
  VkImage depth = VK_NULL_HANDLE;
  VkImageView depthView = VK_NULL_HANDLE;
  VkExtent2D extent{0, 0};
  bool copyable = false;  // color and depth accept copies (the cached ground)
  VkImageLayout finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;  // the color's, after
  // The color image's memory as the host sees it (host-coherent, rows of extent.width * 4
  // bytes, packed), set only while the image holds a finished frame in finalLayout (then
  // GENERAL): the renderer may write the cached backdrop into it from the host, before the
  // commands are submitted, instead of recording a copy.
  uint8_t* hostColor = nullptr;
};

constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

class OffscreenTarget {
 public:
  static constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

  OffscreenTarget(const Device& device, VkExtent2D extent, VkFormat color = kColorFormat);
  // The color image lives in the caller's memory at `host` (VK_EXT_external_memory_host,
  // aligned to hostImportAlignment(), hostBytes() long); the frame leaves it in GENERAL.
  OffscreenTarget(const Device& device, VkExtent2D extent, VkFormat color, void* host);
  // 0 when the device cannot import host memory (the extension was not enabled).
  static VkDeviceSize hostImportAlignment(const Device& device);
  static bool hostColorSupported(const Device& device, VkFormat color);
  // The host memory such a target needs, or nothing when the device would pad its rows or
  // cannot render into host memory (hostColorSupported).
  static std::optional<VkDeviceSize> hostBytes(const Device& device, VkExtent2D extent,
                                               VkFormat color);

  FrameTarget target() const;
  // For a target in host memory that holds a finished frame (the caller waited for it): the
  // same, with hostColor set.
  FrameTarget targetWithHostColor() const;
  VkExtent2D extent() const { return extent_; }
  bool inHostMemory() const { return host_ != nullptr; }
  // After the frame: copy the color image for the host (in host memory: only make the
  // frame's writes visible to the host).
  void recordReadback(VkCommandBuffer commands) const;
  // Once the read-back was submitted and waited on: RGBA8 (or the format's) pixels, rows
  // of extent().width, top row first.
  std::vector<uint8_t> pixels() const;
  const uint8_t* mappedPixels() const;

 private:
  VkExtent2D extent_;
  void* host_ = nullptr;
  bool copyable_;
  Image color_;
  Image depth_;
  ReadbackBuffer readback_;  // empty for a target in host memory
};

}  // namespace lava::host
