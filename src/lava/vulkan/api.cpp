#include "api.h"

#include <string>

#include "lava/error.h"

namespace lava::detail {
namespace {

template <typename F>
void require(F function, const char* name) {
  if (!function) throw ResourceError(std::string("the Vulkan driver does not provide vk") + name);
}

}  // namespace

// Each level's loader below names `get`, its lookup of a function by name (global, instance
// or device), so one pair of macros loads every level: optional, or required (ResourceError).
#define LAVA_VK_OPTIONAL(name) name = reinterpret_cast<PFN_vk##name>(get("vk" #name));
#define LAVA_VK_REQUIRED(name) \
  LAVA_VK_OPTIONAL(name)       \
  require(name, #name);

void Vk::loadGlobal(PFN_vkGetInstanceProcAddr getInstanceProcAddr) {
  GetInstanceProcAddr = getInstanceProcAddr;
  const auto get = [&](const char* name) { return GetInstanceProcAddr(VK_NULL_HANDLE, name); };
  LAVA_VK_GLOBAL(LAVA_VK_OPTIONAL)
}

void Vk::loadInstance(VkInstance instance) {
  const auto get = [&](const char* name) { return GetInstanceProcAddr(instance, name); };
  LAVA_VK_INSTANCE(LAVA_VK_REQUIRED)
  LAVA_VK_OPTIONAL(CreateDebugUtilsMessengerEXT)
  LAVA_VK_OPTIONAL(DestroyDebugUtilsMessengerEXT)
}

void Vk::loadDevice(VkDevice device) {
  const auto get = [&](const char* name) { return GetDeviceProcAddr(device, name); };
  LAVA_VK_DEVICE(LAVA_VK_REQUIRED)
  LAVA_VK_OPTIONAL(CmdPushDescriptorSetKHR)
}

#undef LAVA_VK_REQUIRED
#undef LAVA_VK_OPTIONAL

}  // namespace lava::detail
