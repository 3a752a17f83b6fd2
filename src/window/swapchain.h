// The window's render target through Vulkan presentation: a VkSwapchainKHR over a surface,
// its image views and a depth image, recreated whole when the window changes size.
#pragma once
#include <optional>
#include <vector>

#include "host/vulkan.h"
#include "lava/device.h"
#include "presenter.h"

namespace lava::window {

class Swapchain final : public Presenter {
 public:
  // The color format frames must use for this surface; none when the surface offers none
  // (Mesa presents to X visuals of depth 24 and 32 only).
  static std::optional<VkSurfaceFormatKHR> chooseFormat(const Device& device, VkSurfaceKHR surface);

  Swapchain(const Device& device, VkSurfaceKHR surface, VkSurfaceFormatKHR format, bool vsync,
            uint32_t slots);
  ~Swapchain() override;
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  const char* name() const override;
  uint32_t imageCount() const override { return static_cast<uint32_t>(images_.size()); }
  bool resize(VkExtent2D framebufferSize) override;
  VkExtent2D extent() const override { return extent_; }
  host::FrameTarget acquire(uint32_t slot) override;
  void recordAfterFrame(VkCommandBuffer, uint32_t) override {}
  bool submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) override;

 private:
  void destroyViews();

  const Device& device_;
  VkSurfaceKHR surface_;
  VkSurfaceFormatKHR format_;
  VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
  bool copyable_ = false;  // images and depth accept copies (the cached ground)
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<host::OwnedImageView> views_;
  host::Image depth_;
  std::vector<host::OwnedSemaphore> renderFinished_;  // per image: presentation waits on it
  std::vector<host::OwnedSemaphore> imageAvailable_;  // per slot: rendering waits on it
  uint32_t acquired_ = 0;                             // the image the last acquire() returned
};

}  // namespace lava::window
