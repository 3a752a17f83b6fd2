// The one kind of image Lava and the program create: 2D, one mip, one layer, one sample.
#pragma once
#include <vulkan/vulkan.h>

namespace lava::common {

inline VkImageCreateInfo imageInfo2D(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                                     VkImageTiling tiling = VK_IMAGE_TILING_OPTIMAL) {
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

}  // namespace lava::common
