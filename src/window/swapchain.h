// The window's render target through Vulkan presentation: a VkSwapchainKHR over a surface,
// its image views, a depth image and one framebuffer per image, recreated whole when the
// window changes size.
#pragma once
#include <optional>
#include <vector>

#include "context.h"
#include "offscreen_target.h"
#include "presenter.h"

namespace lava {

class Swapchain final : public Presenter {
 public:
  // The color format the render pass must use for this surface; none when the surface
  // offers none (Mesa presents to X visuals of depth 24 and 32 only).
  static std::optional<VkSurfaceFormatKHR> chooseFormat(const Context& context,
                                                        VkSurfaceKHR surface);

  // `renderPass` renders into images of `format` and leaves them in PRESENT_SRC_KHR.
  Swapchain(const Context& context, VkSurfaceKHR surface, VkRenderPass renderPass,
            VkSurfaceFormatKHR format, bool vsync, uint32_t slots);
  ~Swapchain() override;
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  const char* name() const override;
  uint32_t imageCount() const override { return static_cast<uint32_t>(images_.size()); }
  bool resize(VkExtent2D framebufferSize) override;
  VkExtent2D extent() const override { return extent_; }
  RenderTarget acquire(uint32_t slot) override;
  void recordAfterPass(VkCommandBuffer, uint32_t) override {}
  bool submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) override;

 private:
  void destroyViews();

  const Context& context_;
  VkSurfaceKHR surface_;
  VkRenderPass renderPass_;
  VkSurfaceFormatKHR format_;
  VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
  VkImageUsageFlags copyUsage_ = 0;  // TRANSFER_DST when the images accept copies
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<UniqueImageView> views_;
  ImageWithMemory depth_;
  std::vector<UniqueFramebuffer> framebuffers_;
  std::vector<UniqueSemaphore> renderFinished_;  // per image: presentation waits on it
  std::vector<UniqueSemaphore> imageAvailable_;  // per slot: rendering waits on it
  uint32_t acquired_ = 0;                        // the image the last acquire() returned
};

}  // namespace lava
