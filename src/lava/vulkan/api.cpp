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

void Vk::loadGlobal(PFN_vkGetInstanceProcAddr getInstanceProcAddr) {
  GetInstanceProcAddr = getInstanceProcAddr;
#define LAVA_VK_LOAD(name) \
  name = reinterpret_cast<PFN_vk##name>(GetInstanceProcAddr(VK_NULL_HANDLE, "vk" #name));
  LAVA_VK_GLOBAL(LAVA_VK_LOAD)
#undef LAVA_VK_LOAD
}

void Vk::loadInstance(VkInstance instance) {
#define LAVA_VK_LOAD(name)                                                          \
  name = reinterpret_cast<PFN_vk##name>(GetInstanceProcAddr(instance, "vk" #name)); \
  require(name, #name);
  LAVA_VK_INSTANCE(LAVA_VK_LOAD)
#undef LAVA_VK_LOAD
  CreateDebugUtilsMessengerEXT = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      GetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  DestroyDebugUtilsMessengerEXT = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      GetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
}

void Vk::loadDevice(VkDevice device) {
#define LAVA_VK_LOAD(name)                                                      \
  name = reinterpret_cast<PFN_vk##name>(GetDeviceProcAddr(device, "vk" #name)); \
  require(name, #name);
  LAVA_VK_DEVICE(LAVA_VK_LOAD)
#undef LAVA_VK_LOAD
  CmdPushDescriptorSetKHR = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      GetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR"));
}

}  // namespace lava::detail
