#include "swapchain.h"

#include <algorithm>

namespace lava::window {
namespace {

host::OwnedSemaphore createSemaphore(VkDevice device) {
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore semaphore = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSemaphore(device, &info, nullptr, &semaphore));
  return host::OwnedSemaphore(device, semaphore);
}

}  // namespace

std::optional<VkSurfaceFormatKHR> Swapchain::chooseFormat(const Device& device,
                                                          VkSurfaceKHR surface) {
  VkPhysicalDevice physical = device.handles().physicalDevice;
  uint32_t count = 0;
  VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data()));
  if (formats.empty()) return std::nullopt;
  // UNORM like the offscreen target, so window and PNG frames look the same.
  for (const VkSurfaceFormatKHR& f : formats)
    if ((f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
        f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
      return f;
  return formats.front();
}

Swapchain::Swapchain(const Device& device, VkSurfaceKHR surface, VkSurfaceFormatKHR format,
                     bool vsync, uint32_t slots)
    : device_(device), surface_(surface), format_(format) {
  VkPhysicalDevice physical = device.handles().physicalDevice;
  for (uint32_t i = 0; i < slots; ++i)
    imageAvailable_.push_back(createSemaphore(device.handles().device));
  VkBool32 supported = VK_FALSE;
  VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(physical, device.handles().queueFamily, surface,
                                                  &supported));
  if (!supported) throw ResourceError("the chosen device cannot present to this window");
  if (!vsync) {
    uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(physical, surface, &count, nullptr));
    std::vector<VkPresentModeKHR> modes(count);
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(physical, surface, &count, modes.data()));
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
      if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) {
        presentMode_ = wanted;
        break;
      }
  }
}

Swapchain::~Swapchain() {
  destroyViews();
  if (swapchain_) vkDestroySwapchainKHR(device_.handles().device, swapchain_, nullptr);
}

const char* Swapchain::name() const {
  switch (presentMode_) {
    case VK_PRESENT_MODE_MAILBOX_KHR:
      return "mailbox";
    case VK_PRESENT_MODE_IMMEDIATE_KHR:
      return "immediate";
    default:
      return "fifo (vsync)";
  }
}

void Swapchain::destroyViews() {
  renderFinished_.clear();
  depth_ = {};
  views_.clear();
  images_.clear();
}

bool Swapchain::resize(VkExtent2D framebufferSize) {
  VkDevice device = device_.handles().device;
  VK_CHECK(vkDeviceWaitIdle(device));
  VkSurfaceCapabilitiesKHR caps;
  VK_CHECK(
      vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_.handles().physicalDevice, surface_, &caps));
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX) {
    extent.width =
        std::clamp(framebufferSize.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height =
        std::clamp(framebufferSize.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  if (extent.width == 0 || extent.height == 0) return false;  // minimised: nothing to draw into

  uint32_t imageCount = std::max(caps.minImageCount + 1, 3u);
  if (caps.maxImageCount > 0) imageCount = std::min(imageCount, caps.maxImageCount);
  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  info.minImageCount = imageCount;
  info.imageFormat = format_.format;
  info.imageColorSpace = format_.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  copyable_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT) &&
              host::copyTargetUsage(device_, host::kDepthFormat);
  info.imageUsage =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (copyable_ ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : 0);
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = presentMode_;
  info.clipped = VK_TRUE;
  info.oldSwapchain = swapchain_;
  VkSwapchainKHR created = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSwapchainKHR(device, &info, nullptr, &created));
  destroyViews();
  if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
  swapchain_ = created;
  extent_ = extent;

  uint32_t count = 0;
  VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, nullptr));
  images_.resize(count);
  VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, images_.data()));
  depth_ = host::createImage(device_, extent, host::kDepthFormat,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                 VK_IMAGE_USAGE_SAMPLED_BIT |
                                 (copyable_ ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : 0),
                             VK_IMAGE_ASPECT_DEPTH_BIT);
  for (VkImage image : images_) {
    views_.push_back(host::createView(device_, image, format_.format, VK_IMAGE_ASPECT_COLOR_BIT));
    renderFinished_.push_back(createSemaphore(device));
  }
  return true;
}

host::FrameTarget Swapchain::acquire(uint32_t slot) {
  const VkResult acquired =
      vkAcquireNextImageKHR(device_.handles().device, swapchain_, UINT64_MAX, imageAvailable_[slot],
                            VK_NULL_HANDLE, &acquired_);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return {};
  if (acquired != VK_SUBOPTIMAL_KHR) VK_CHECK(acquired);
  host::FrameTarget target;
  target.color = images_[acquired_];
  target.colorView = views_[acquired_];
  target.depth = depth_.image;
  target.depthView = depth_.view;
  target.extent = extent_;
  target.copyable = copyable_;
  target.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  return target;
}

bool Swapchain::submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) {
  VkSemaphore wait = imageAvailable_[slot];
  VkSemaphore signal = renderFinished_[acquired_];
  // The image is first written by the pass or by the copy of the cached ground.
  VkPipelineStageFlags waitStage =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &wait;
  submit.pWaitDstStageMask = &waitStage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &signal;
  VK_CHECK(vkQueueSubmit(device_.handles().queue, 1, &submit, done));

  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &signal;
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &acquired_;
  const VkResult presented = vkQueuePresentKHR(device_.handles().queue, &present);
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) return false;
  VK_CHECK(presented);
  return true;
}

}  // namespace lava::window
