#include "swapchain.h"

#include <algorithm>

#include "line_renderer.h"
#include "vk_check.h"

namespace lava {
namespace {

UniqueSemaphore createSemaphore(VkDevice device) {
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore semaphore = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSemaphore(device, &info, nullptr, &semaphore));
  return UniqueSemaphore(device, semaphore);
}

}  // namespace

std::optional<VkSurfaceFormatKHR> Swapchain::chooseFormat(const Context& context,
                                                          VkSurfaceKHR surface) {
  uint32_t count = 0;
  VK_CHECK(
      vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice(), surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice(), surface, &count,
                                                formats.data()));
  if (formats.empty()) return std::nullopt;
  // UNORM like the offscreen target, so window and PNG frames look the same.
  for (const VkSurfaceFormatKHR& f : formats)
    if ((f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
        f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
      return f;
  return formats.front();
}

Swapchain::Swapchain(const Context& context, VkSurfaceKHR surface, VkRenderPass renderPass,
                     VkSurfaceFormatKHR format, bool vsync, uint32_t slots)
    : context_(context), surface_(surface), renderPass_(renderPass), format_(format) {
  for (uint32_t i = 0; i < slots; ++i) imageAvailable_.push_back(createSemaphore(context.device()));
  VkBool32 supported = VK_FALSE;
  VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(context.physicalDevice(), context.queueFamily(),
                                                surface, &supported));
  if (!supported) throw ResourceError("the chosen device cannot present to this window");
  if (!vsync) {
    uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context.physicalDevice(), surface, &count,
                                                       nullptr));
    std::vector<VkPresentModeKHR> modes(count);
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context.physicalDevice(), surface, &count,
                                                       modes.data()));
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
      if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) {
        presentMode_ = wanted;
        break;
      }
  }
}

Swapchain::~Swapchain() {
  destroyViews();
  if (swapchain_) vkDestroySwapchainKHR(context_.device(), swapchain_, nullptr);
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
  framebuffers_.clear();
  depth_ = {};
  views_.clear();
  images_.clear();
}

bool Swapchain::resize(VkExtent2D framebufferSize) {
  VkDevice device = context_.device();
  VK_CHECK(vkDeviceWaitIdle(device));
  VkSurfaceCapabilitiesKHR caps;
  VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context_.physicalDevice(), surface_, &caps));
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
  copyUsage_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT) &&
                       copyTargetUsage(context_, LineRenderer::kDepthFormat)
                   ? VK_IMAGE_USAGE_TRANSFER_DST_BIT
                   : 0;
  info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | copyUsage_;
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
  depth_ = createImage(context_, extent, LineRenderer::kDepthFormat,
                       VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | copyUsage_,
                       VK_IMAGE_ASPECT_DEPTH_BIT);
  for (VkImage image : images_) {
    views_.push_back(createImageView(device, image, format_.format, VK_IMAGE_ASPECT_COLOR_BIT));
    framebuffers_.push_back(
        createFramebuffer(device, renderPass_, views_.back(), depth_.view, extent));
    renderFinished_.push_back(createSemaphore(device));
  }
  return true;
}

RenderTarget Swapchain::acquire(uint32_t slot) {
  const VkResult acquired = vkAcquireNextImageKHR(
      context_.device(), swapchain_, UINT64_MAX, imageAvailable_[slot], VK_NULL_HANDLE, &acquired_);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return {};
  if (acquired != VK_SUBOPTIMAL_KHR) VK_CHECK(acquired);
  if (!copyUsage_) return {framebuffers_[acquired_], extent_};
  return {framebuffers_[acquired_], extent_, images_[acquired_], depth_.image};
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
  VK_CHECK(vkQueueSubmit(context_.queue(), 1, &submit, done));

  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &signal;
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &acquired_;
  const VkResult presented = vkQueuePresentKHR(context_.queue(), &present);
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) return false;
  VK_CHECK(presented);
  return true;
}

}  // namespace lava
