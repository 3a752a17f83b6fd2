#include "offscreen_target.h"

#include <cstring>

#include "descriptors.h"
#include "line_renderer.h"
#include "vk_check.h"

namespace lava {

ImageWithMemory createImage(const Context& context, VkExtent2D extent, VkFormat format,
                            VkImageUsageFlags usage, VkImageAspectFlags aspect) {
  VkDevice device = context.device();
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImage(device, &info, nullptr, &image));
  ImageWithMemory out;
  out.image = UniqueImage(device, image);

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, image, &requirements);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = requirements.size;
  alloc.memoryTypeIndex =
      context.findMemoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &memory));
  out.memory = UniqueMemory(device, memory);
  VK_CHECK(vkBindImageMemory(device, image, memory, 0));

  out.view = createImageView(device, image, format, aspect);
  return out;
}

UniqueImageView createImageView(VkDevice device, VkImage image, VkFormat format,
                                VkImageAspectFlags aspect) {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image;
  info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  info.format = format;
  info.subresourceRange = {aspect, 0, 1, 0, 1};
  VkImageView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImageView(device, &info, nullptr, &view));
  return UniqueImageView(device, view);
}

VkImageUsageFlags copyTargetUsage(const Context& context, VkFormat format) {
  VkFormatProperties properties;
  vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), format, &properties);
  return (properties.optimalTilingFeatures & VK_FORMAT_FEATURE_TRANSFER_DST_BIT)
             ? VK_IMAGE_USAGE_TRANSFER_DST_BIT
             : 0;
}

OffscreenTarget::OffscreenTarget(const Context& context, VkRenderPass renderPass, VkExtent2D extent,
                                 VkFormat colorFormat, void* readbackHost)
    : extent_(extent),
      copyable_(copyTargetUsage(context, colorFormat) &&
                copyTargetUsage(context, LineRenderer::kDepthFormat)),
      color_(createImage(context, extent, colorFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                             (copyable_ ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : 0u),
                         VK_IMAGE_ASPECT_COLOR_BIT)),
      depth_(createImage(context, extent, LineRenderer::kDepthFormat,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                             (copyable_ ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : 0u),
                         VK_IMAGE_ASPECT_DEPTH_BIT)),
      readback_(readbackHost
                    ? Buffer(context, readbackHost, readbackBytes(extent),
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT)
                    : Buffer(context, readbackBytes(extent), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                 VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)) {
  framebuffer_ = createFramebuffer(context.device(), renderPass, color_.view, depth_.view, extent);
}

UniqueFramebuffer createFramebuffer(VkDevice device, VkRenderPass renderPass, VkImageView color,
                                    VkImageView depth, VkExtent2D extent) {
  const VkImageView views[2] = {color, depth};
  VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  info.renderPass = renderPass;
  info.attachmentCount = 2;
  info.pAttachments = views;
  info.width = extent.width;
  info.height = extent.height;
  info.layers = 1;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFramebuffer(device, &info, nullptr, &framebuffer));
  return UniqueFramebuffer(device, framebuffer);
}

void OffscreenTarget::recordReadback(VkCommandBuffer commands) const {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent_.width, extent_.height, 1};
  vkCmdCopyImageToBuffer(commands, color_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         readback_.get(), 1, &region);
  // RAW: the host reads what the copy wrote.
  memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

std::vector<uint8_t> OffscreenTarget::pixels() const {
  std::vector<uint8_t> out(readback_.size());
  std::memcpy(out.data(), readback_.mapped(), out.size());
  return out;
}

std::vector<uint8_t> renderOffscreen(const Context& context, LineRenderer& renderer,
                                     const OffscreenTarget& target, const OrbitCamera& camera,
                                     const Scene& scene) {
  context.submitNow([&](VkCommandBuffer commands) {
    renderer.record(commands, target.target(), camera, scene);
    target.recordReadback(commands);
  });
  return target.pixels();
}

}  // namespace lava
