// The window's render target: a VkSwapchainKHR over a surface, its image views, a depth
// image and one framebuffer per image, recreated whole when the window changes size.
#pragma once
#include <vector>

#include "context.h"
#include "offscreen_target.h"

namespace lava {

class Swapchain {
 public:
  // The color format the render pass must use for this surface.
  static VkSurfaceFormatKHR chooseFormat(const Context& context, VkSurfaceKHR surface);

  Swapchain(const Context& context, VkSurfaceKHR surface, VkRenderPass renderPass,
            VkSurfaceFormatKHR format, bool vsync);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Rebuilds for the surface's current size; returns false while it is 0x0 (minimised).
  bool recreate(VkExtent2D framebufferSize);
  VkSwapchainKHR get() const { return swapchain_; }
  VkExtent2D extent() const { return extent_; }
  uint32_t imageCount() const { return static_cast<uint32_t>(images_.size()); }
  VkFramebuffer framebuffer(uint32_t image) const { return framebuffers_[image]; }
  // Signalled when rendering into `image` is done; presentation waits on it.
  VkSemaphore renderFinished(uint32_t image) const { return renderFinished_[image]; }
  const char* presentModeName() const;

 private:
  void destroyViews();

  const Context& context_;
  VkSurfaceKHR surface_;
  VkRenderPass renderPass_;
  VkSurfaceFormatKHR format_;
  VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<UniqueImageView> views_;
  ImageWithMemory depth_;
  std::vector<UniqueFramebuffer> framebuffers_;
  std::vector<UniqueSemaphore> renderFinished_;
};

}  // namespace lava
