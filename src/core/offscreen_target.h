// A render target with no window: a color and a depth image, their framebuffer, and a
// host-visible buffer the color image is copied into for reading back.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "buffer.h"
#include "context.h"

namespace lava {

// Where LineRenderer::record() draws: a framebuffer of its render pass and its size; and
// its color and depth images when they were made with TRANSFER_DST usage (else null: the
// renderer then draws the ground instead of copying its cached one in).
struct RenderTarget {
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkExtent2D extent{0, 0};
  VkImage color = VK_NULL_HANDLE;
  VkImage depth = VK_NULL_HANDLE;
};

// TRANSFER_DST when `format` accepts copies into optimal-tiling images on this device.
VkImageUsageFlags copyTargetUsage(const Context& context, VkFormat format);

struct ImageWithMemory {
  UniqueImage image;
  UniqueMemory memory;
  UniqueImageView view;
};

UniqueImageView createImageView(VkDevice device, VkImage image, VkFormat format,
                                VkImageAspectFlags aspect);
// A framebuffer of LineRenderer's render pass: a color and a depth attachment.
UniqueFramebuffer createFramebuffer(VkDevice device, VkRenderPass renderPass, VkImageView color,
                                    VkImageView depth, VkExtent2D extent);
// A 2D image in device-local memory with a view of `aspect`.
ImageWithMemory createImage(const Context& context, VkExtent2D extent, VkFormat format,
                            VkImageUsageFlags usage, VkImageAspectFlags aspect);

class OffscreenTarget {
 public:
  static constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

  // `finalLayout`: the color image's layout after the render pass.
  OffscreenTarget(const Context& context, VkRenderPass renderPass, VkExtent2D extent,
                  VkFormat colorFormat = kColorFormat,
                  VkImageLayout finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  // A target whose color image is a linear image in the caller's host memory at `host`
  // (VK_EXT_external_memory_host, aligned to Context::hostImportAlignment(), *hostBytes()
  // long): the pass writes the pixels there, rows packed, with no read-back copy. The pass
  // must leave it in GENERAL. Check hostColorSupported() and hostBytes() first.
  OffscreenTarget(const Context& context, VkRenderPass renderPass, VkExtent2D extent,
                  VkFormat colorFormat, void* host);
  static bool hostColorSupported(const Context& context, VkFormat colorFormat);
  // The host memory such a target needs at this size, or nothing when the device would
  // pad its rows (the pixels would not be packed).
  static std::optional<VkDeviceSize> hostBytes(const Context& context, VkExtent2D extent,
                                               VkFormat colorFormat);
  RenderTarget target() const {
    return {framebuffer_, extent_, copyable_ ? color_.image.get() : VK_NULL_HANDLE,
            copyable_ ? depth_.image.get() : VK_NULL_HANDLE};
  }
  VkExtent2D extent() const { return extent_; }
  // Whether the color image is the caller's host memory (the host-memory constructor).
  bool inHostMemory() const { return host_ != nullptr; }
  // After the render pass: copy the image for the host (or, in host memory, only make the
  // pass's writes visible to it).
  void recordReadback(VkCommandBuffer commands) const;
  // RGBA8 pixels, row-major from the top-left, once the readback was submitted and waited on.
  std::vector<uint8_t> pixels() const;
  // The same pixels in place: 4 bytes each, rows of extent().width, no padding.
  const uint8_t* mappedPixels() const {
    return static_cast<const uint8_t*>(host_ ? host_ : readback_.mapped());
  }

 private:
  VkExtent2D extent_;
  VkImageLayout finalLayout_;
  void* host_ = nullptr;  // the color image's memory, when it is the caller's
  bool copyable_;
  ImageWithMemory color_;
  ImageWithMemory depth_;
  UniqueFramebuffer framebuffer_;
  Buffer readback_;
};

class LineRenderer;
struct OrbitCamera;
struct Scene;

// Renders the simulator's current particles into `target` and returns its pixels.
std::vector<uint8_t> renderOffscreen(const Context& context, LineRenderer& renderer,
                                     const OffscreenTarget& target, const OrbitCamera& camera,
                                     const Scene& scene);

}  // namespace lava
