#include "offscreen_target.h"

#include <algorithm>
#include <cstring>

#include "descriptors.h"
#include "line_renderer.h"
#include "vk_check.h"

namespace lava {

namespace {

// A single-sample 2D image, one mip and one layer, starting UNDEFINED.
VkImageCreateInfo imageInfo(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                            VkImageTiling tiling) {
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = tiling;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  return info;
}

}  // namespace

ImageWithMemory createImage(const Context& context, VkExtent2D extent, VkFormat format,
                            VkImageUsageFlags usage, VkImageAspectFlags aspect) {
  VkDevice device = context.device();
  const VkImageCreateInfo info = imageInfo(extent, format, usage, VK_IMAGE_TILING_OPTIMAL);
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
                                 VkFormat colorFormat, VkImageLayout finalLayout)
    : extent_(extent),
      finalLayout_(finalLayout),
      copyable_(copyTargetUsage(context, colorFormat) &&
                copyTargetUsage(context, LineRenderer::kDepthFormat)),
      color_(createImage(context, extent, colorFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                             copyTargetUsage(context, colorFormat),
                         VK_IMAGE_ASPECT_COLOR_BIT)),
      depth_(createImage(context, extent, LineRenderer::kDepthFormat,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                             copyTargetUsage(context, LineRenderer::kDepthFormat),
                         VK_IMAGE_ASPECT_DEPTH_BIT)),
      readback_(context, VkDeviceSize{extent.width} * extent.height * 4,
                VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) {
  framebuffer_ = createFramebuffer(context.device(), renderPass, color_.view, depth_.view, extent);
}

namespace {

constexpr auto kHostHandle = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT;
constexpr VkImageUsageFlags kHostColorUsage =
    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

UniqueImage createHostColorImage(VkDevice device, VkExtent2D extent, VkFormat format) {
  VkExternalMemoryImageCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_IMAGE_CREATE_INFO};
  external.handleTypes = kHostHandle;
  VkImageCreateInfo info = imageInfo(extent, format, kHostColorUsage, VK_IMAGE_TILING_LINEAR);
  info.pNext = &external;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImage(device, &info, nullptr, &image));
  return UniqueImage(device, image);
}

// A linear color image over the caller's memory at `host` (hostBytes() long).
ImageWithMemory importHostColorImage(const Context& context, VkExtent2D extent, VkFormat format,
                                     void* host) {
  const std::optional<VkDeviceSize> bytes = OffscreenTarget::hostBytes(context, extent, format);
  if (!bytes) throw ResourceError("this device pads the rows of a linear color image");
  VkDevice device = context.device();
  ImageWithMemory out;
  out.image = createHostColorImage(device, extent, format);
  auto hostPointerProperties = reinterpret_cast<PFN_vkGetMemoryHostPointerPropertiesEXT>(
      vkGetDeviceProcAddr(device, "vkGetMemoryHostPointerPropertiesEXT"));
  VkMemoryHostPointerPropertiesEXT pointer{VK_STRUCTURE_TYPE_MEMORY_HOST_POINTER_PROPERTIES_EXT};
  VK_CHECK(hostPointerProperties(device, kHostHandle, host, &pointer));
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, out.image, &requirements);
  VkImportMemoryHostPointerInfoEXT import{VK_STRUCTURE_TYPE_IMPORT_MEMORY_HOST_POINTER_INFO_EXT};
  import.handleType = kHostHandle;
  import.pHostPointer = host;
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.pNext = &import;
  alloc.allocationSize = *bytes;
  alloc.memoryTypeIndex = context.findMemoryType(
      requirements.memoryTypeBits & pointer.memoryTypeBits,
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &memory));
  out.memory = UniqueMemory(device, memory);
  VK_CHECK(vkBindImageMemory(device, out.image, memory, 0));
  out.view = createImageView(device, out.image, format, VK_IMAGE_ASPECT_COLOR_BIT);
  return out;
}

}  // namespace

bool OffscreenTarget::hostColorSupported(const Context& context, VkFormat colorFormat) {
  if (context.hostImportAlignment() == 0) return false;
  VkPhysicalDeviceExternalImageFormatInfo external{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_IMAGE_FORMAT_INFO};
  external.handleType = kHostHandle;
  VkPhysicalDeviceImageFormatInfo2 info{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_IMAGE_FORMAT_INFO_2};
  info.pNext = &external;
  info.format = colorFormat;
  info.type = VK_IMAGE_TYPE_2D;
  info.tiling = VK_IMAGE_TILING_LINEAR;
  info.usage = kHostColorUsage;
  VkExternalImageFormatProperties externalProperties{
      VK_STRUCTURE_TYPE_EXTERNAL_IMAGE_FORMAT_PROPERTIES};
  VkImageFormatProperties2 properties{VK_STRUCTURE_TYPE_IMAGE_FORMAT_PROPERTIES_2};
  properties.pNext = &externalProperties;
  return vkGetPhysicalDeviceImageFormatProperties2(context.physicalDevice(), &info, &properties) ==
             VK_SUCCESS &&
         (externalProperties.externalMemoryProperties.externalMemoryFeatures &
          VK_EXTERNAL_MEMORY_FEATURE_IMPORTABLE_BIT) &&
         copyTargetUsage(context, LineRenderer::kDepthFormat);
}

std::optional<VkDeviceSize> OffscreenTarget::hostBytes(const Context& context, VkExtent2D extent,
                                                       VkFormat colorFormat) {
  VkDevice device = context.device();
  const UniqueImage probe = createHostColorImage(device, extent, colorFormat);
  VkImageSubresource color{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0};
  VkSubresourceLayout layout;
  vkGetImageSubresourceLayout(device, probe, &color, &layout);
  if (layout.offset != 0 || layout.rowPitch != VkDeviceSize{extent.width} * 4) return {};
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, probe, &requirements);
  const VkDeviceSize alignment =
      std::max<VkDeviceSize>({context.hostImportAlignment(), requirements.alignment, 1});
  const VkDeviceSize bytes =
      std::max(requirements.size, VkDeviceSize{extent.width} * extent.height * 4);
  return (bytes + alignment - 1) / alignment * alignment;
}

OffscreenTarget::OffscreenTarget(const Context& context, VkRenderPass renderPass, VkExtent2D extent,
                                 VkFormat colorFormat, void* host)
    : extent_(extent),
      finalLayout_(VK_IMAGE_LAYOUT_GENERAL),
      host_(host),
      copyable_(true),
      color_(importHostColorImage(context, extent, colorFormat, host)),
      depth_(
          createImage(context, extent, LineRenderer::kDepthFormat,
                      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT)) {
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
  if (host_) {
    // RAW: the host reads what the pass wrote, in place.
    memoryBarrier(commands, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                  VK_ACCESS_HOST_READ_BIT);
    return;
  }
  if (finalLayout_ != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) {
    // RAW: the copy reads what the pass wrote; into the layout copies read best.
    imageBarrier(commands, color_.image, VK_IMAGE_ASPECT_COLOR_BIT, finalLayout_,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
  }
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
  std::vector<uint8_t> out(size_t(extent_.width) * extent_.height * 4);
  std::memcpy(out.data(), mappedPixels(), out.size());
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
