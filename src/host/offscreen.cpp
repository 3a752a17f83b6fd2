#include "offscreen.h"

#include <algorithm>
#include <cstring>

#include "common/images.h"

namespace lava::host {
namespace {

constexpr auto kHostHandle = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT;
constexpr VkImageUsageFlags kHostColorUsage =
    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

OwnedImage createHostColorImage(VkDevice device, VkExtent2D extent, VkFormat format) {
  VkExternalMemoryImageCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_IMAGE_CREATE_INFO};
  external.handleTypes = kHostHandle;
  VkImageCreateInfo info =
      common::imageInfo2D(extent, format, kHostColorUsage, VK_IMAGE_TILING_LINEAR);
  info.pNext = &external;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImage(device, &info, nullptr, &image));
  return OwnedImage(device, image);
}

Image importHostColorImage(const Device& device, VkExtent2D extent, VkFormat format, void* host) {
  const std::optional<VkDeviceSize> bytes = OffscreenTarget::hostBytes(device, extent, format);
  if (!bytes) throw ResourceError("this device pads the rows of a linear color image");
  VkDevice handle = device.handles().device;
  Image out;
  out.image = createHostColorImage(handle, extent, format);
  auto pointerProperties = reinterpret_cast<PFN_vkGetMemoryHostPointerPropertiesEXT>(
      vkGetDeviceProcAddr(handle, "vkGetMemoryHostPointerPropertiesEXT"));
  if (!pointerProperties) throw ResourceError("VK_EXT_external_memory_host is not enabled");
  VkMemoryHostPointerPropertiesEXT pointer{VK_STRUCTURE_TYPE_MEMORY_HOST_POINTER_PROPERTIES_EXT};
  VK_CHECK(pointerProperties(handle, kHostHandle, host, &pointer));
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(handle, out.image, &requirements);
  VkImportMemoryHostPointerInfoEXT import{VK_STRUCTURE_TYPE_IMPORT_MEMORY_HOST_POINTER_INFO_EXT};
  import.handleType = kHostHandle;
  import.pHostPointer = host;
  out.memory = allocate(
      device, *bytes,
      memoryType(device, requirements.memoryTypeBits & pointer.memoryTypeBits,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT),
      &import);
  VK_CHECK(vkBindImageMemory(handle, out.image, out.memory, 0));
  out.view = createView(device, out.image, format, VK_IMAGE_ASPECT_COLOR_BIT);
  return out;
}

}  // namespace

VkDeviceSize OffscreenTarget::hostImportAlignment(const Device& device) {
  if (!device.hasExtension(VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME)) return 0;
  VkPhysicalDeviceExternalMemoryHostPropertiesEXT host{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_MEMORY_HOST_PROPERTIES_EXT};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &host;
  vkGetPhysicalDeviceProperties2(device.handles().physicalDevice, &properties);
  return host.minImportedHostPointerAlignment;
}

bool OffscreenTarget::hostColorSupported(const Device& device, VkFormat color) {
  if (hostImportAlignment(device) == 0) return false;
  VkPhysicalDeviceExternalImageFormatInfo external{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_IMAGE_FORMAT_INFO};
  external.handleType = kHostHandle;
  VkPhysicalDeviceImageFormatInfo2 info{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_IMAGE_FORMAT_INFO_2};
  info.pNext = &external;
  info.format = color;
  info.type = VK_IMAGE_TYPE_2D;
  info.tiling = VK_IMAGE_TILING_LINEAR;
  info.usage = kHostColorUsage;
  VkExternalImageFormatProperties externalProperties{
      VK_STRUCTURE_TYPE_EXTERNAL_IMAGE_FORMAT_PROPERTIES};
  VkImageFormatProperties2 properties{VK_STRUCTURE_TYPE_IMAGE_FORMAT_PROPERTIES_2};
  properties.pNext = &externalProperties;
  return vkGetPhysicalDeviceImageFormatProperties2(device.handles().physicalDevice, &info,
                                                   &properties) == VK_SUCCESS &&
         (externalProperties.externalMemoryProperties.externalMemoryFeatures &
          VK_EXTERNAL_MEMORY_FEATURE_IMPORTABLE_BIT) &&
         copyTargetUsage(device, kDepthFormat);
}

std::optional<VkDeviceSize> OffscreenTarget::hostBytes(const Device& device, VkExtent2D extent,
                                                       VkFormat color) {
  if (!hostColorSupported(device, color)) return {};  // the probe would be invalid
  VkDevice handle = device.handles().device;
  const OwnedImage probe = createHostColorImage(handle, extent, color);
  VkImageSubresource subresource{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0};
  VkSubresourceLayout layout;
  vkGetImageSubresourceLayout(handle, probe, &subresource, &layout);
  if (layout.offset != 0 || layout.rowPitch != VkDeviceSize{extent.width} * 4) return {};
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(handle, probe, &requirements);
  const VkDeviceSize alignment =
      std::max<VkDeviceSize>({hostImportAlignment(device), requirements.alignment, 1});
  const VkDeviceSize bytes =
      std::max(requirements.size, VkDeviceSize{extent.width} * extent.height * 4);
  return (bytes + alignment - 1) / alignment * alignment;
}

OffscreenTarget::OffscreenTarget(const Device& device, VkExtent2D extent, VkFormat color)
    : extent_(extent),
      copyable_(copyTargetUsage(device, color) && copyTargetUsage(device, kDepthFormat)),
      color_(createImage(device, extent, color,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                             copyTargetUsage(device, color),
                         VK_IMAGE_ASPECT_COLOR_BIT)),
      depth_(createImage(device, extent, kDepthFormat,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                             copyTargetUsage(device, kDepthFormat),
                         VK_IMAGE_ASPECT_DEPTH_BIT)),
      readback_(device, VkDeviceSize{extent.width} * extent.height * 4) {}

OffscreenTarget::OffscreenTarget(const Device& device, VkExtent2D extent, VkFormat color,
                                 void* host)
    : extent_(extent),
      host_(host),
      copyable_(true),
      color_(importHostColorImage(device, extent, color, host)),
      depth_(createImage(device, extent, kDepthFormat,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                             VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                         VK_IMAGE_ASPECT_DEPTH_BIT)) {}

FrameTarget OffscreenTarget::target() const {
  FrameTarget t;
  t.color = color_.image;
  t.colorView = color_.view;
  t.depth = depth_.image;
  t.depthView = depth_.view;
  t.extent = extent_;
  t.copyable = copyable_;
  t.finalLayout = host_ ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  return t;
}

FrameTarget OffscreenTarget::targetWithHostColor() const {
  FrameTarget t = target();
  t.hostColor = static_cast<uint8_t*>(host_);
  return t;
}

void OffscreenTarget::recordReadback(VkCommandBuffer commands) const {
  if (host_) {
    // RAW: the host reads what the frame wrote, in place.
    memoryBarrier(commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                  VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    return;
  }
  readback_.recordCopy(commands, color_.image, extent_);
}

const uint8_t* OffscreenTarget::mappedPixels() const {
  if (host_) return static_cast<const uint8_t*>(host_);
  return static_cast<const uint8_t*>(readback_.read());
}

std::vector<uint8_t> OffscreenTarget::pixels() const {
  std::vector<uint8_t> out(size_t(extent_.width) * extent_.height * 4);
  std::memcpy(out.data(), mappedPixels(), out.size());
  return out;
}

void copyRows(uint8_t* destination, size_t pitch, const uint8_t* source, size_t row,
              uint32_t height) {
  if (pitch == row) {
    std::memcpy(destination, source, row * height);
    return;
  }
  for (uint32_t y = 0; y < height; ++y)
    std::memcpy(destination + size_t(y) * pitch, source + size_t(y) * row, row);
}

}  // namespace lava::host
