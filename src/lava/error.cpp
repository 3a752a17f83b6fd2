#include "lava/error.h"

#include "lava/version.h"

namespace lava {

InvalidArgument::InvalidArgument(std::string parameter, std::string detail)
    : Error(parameter + ": " + detail),
      parameter_(std::move(parameter)),
      detail_(std::move(detail)) {}

VulkanError::VulkanError(VkResult result, const std::string& call, const char* file, int line)
    : Error(call + " failed with " + resultName(result) + " at " + file + ":" +
            std::to_string(line)),
      result_(result) {}

std::string resultName(VkResult result) {
  switch (result) {
#define LAVA_CASE(r) \
  case r:            \
    return #r;
    LAVA_CASE(VK_SUCCESS)
    LAVA_CASE(VK_NOT_READY)
    LAVA_CASE(VK_TIMEOUT)
    LAVA_CASE(VK_EVENT_SET)
    LAVA_CASE(VK_EVENT_RESET)
    LAVA_CASE(VK_INCOMPLETE)
    LAVA_CASE(VK_SUBOPTIMAL_KHR)
    LAVA_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    LAVA_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    LAVA_CASE(VK_ERROR_INITIALIZATION_FAILED)
    LAVA_CASE(VK_ERROR_DEVICE_LOST)
    LAVA_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    LAVA_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    LAVA_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    LAVA_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    LAVA_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    LAVA_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    LAVA_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    LAVA_CASE(VK_ERROR_FRAGMENTED_POOL)
    LAVA_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    LAVA_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    LAVA_CASE(VK_ERROR_FRAGMENTATION)
    LAVA_CASE(VK_ERROR_SURFACE_LOST_KHR)
    LAVA_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
    LAVA_CASE(VK_ERROR_OUT_OF_DATE_KHR)
    LAVA_CASE(VK_ERROR_INCOMPATIBLE_DISPLAY_KHR)
    LAVA_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
    LAVA_CASE(VK_ERROR_UNKNOWN)
#undef LAVA_CASE
    default:
      return "VkResult " + std::to_string(static_cast<int>(result));
  }
}

const char* versionString() {
  return LAVA_VERSION_STRING;
}

}  // namespace lava
