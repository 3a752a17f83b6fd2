#include "context.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "vk_check.h"

namespace lava {
namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool hasLayer(const char* name) {
  uint32_t count = 0;
  VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
  std::vector<VkLayerProperties> layers(count);
  VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, name) == 0;
  });
}

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

unsigned parseDeviceIndex(const char* source, const char* text, size_t count) {
  char* end = nullptr;
  errno = 0;
  unsigned long value = std::strtoul(text, &end, 10);
  if (*text == '\0' || *end != '\0' || errno != 0 || text[0] == '-' || value >= count)
    throw UsageError(std::string(source) + ": expected a device index in [0, " +
                     std::to_string(count - 1) + "], got '" + text + "' (see 'lava info')");
  return static_cast<unsigned>(value);
}

}  // namespace

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

namespace {

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  for (const VkExtensionProperties& e : extensions)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

}  // namespace

Context::Context(const ContextOptions& options) {
  if (options.validation && !hasLayer(kValidationLayer))
    throw ResourceError(
        "the Vulkan validation layer is not installed (Debian: vulkan-validationlayers)");

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "lava";
  app.apiVersion = VK_API_VERSION_1_2;

  std::vector<const char*> extensions = options.instanceExtensions;
  std::vector<const char*> layers;
  VkDebugUtilsMessengerCreateInfoEXT messengerInfo{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                  VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messengerInfo.pfnUserCallback = &Context::onMessage;
  messengerInfo.pUserData = this;
  VkValidationFeatureEnableEXT syncFeature =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &syncFeature;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  if (options.validation) {
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (options.syncValidation) messengerInfo.pNext = &features;
    info.pNext = &messengerInfo;
  }
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkResult created = vkCreateInstance(&info, nullptr, &instance_);
  if (created == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw ResourceError(
        "no Vulkan driver found (install one, e.g. Debian's mesa-vulkan-drivers for lavapipe)");
  VK_CHECK(created);

  try {
    if (options.validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      messengerInfo.pNext = nullptr;
      VK_CHECK(create(instance_, &messengerInfo, nullptr, &messenger_));
    }
    pickDevice(options);

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, families.data());
    const VkQueueFlags both = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    auto it = std::find_if(families.begin(), families.end(), [&](const VkQueueFamilyProperties& f) {
      return (f.queueFlags & both) == both;
    });
    if (it == families.end())
      throw ResourceError(std::string("device '") + properties_.deviceName +
                          "' has no queue with both graphics and compute");
    queueFamily_ = static_cast<uint32_t>(it - families.begin());

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = queueFamily_;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    std::vector<const char*> deviceExtensions;
    if (options.swapchain) deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    if (options.hostImport &&
        hasDeviceExtension(physical_, VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME)) {
      deviceExtensions.push_back(VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME);
      VkPhysicalDeviceExternalMemoryHostPropertiesEXT host{
          VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_MEMORY_HOST_PROPERTIES_EXT};
      VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
      properties2.pNext = &host;
      vkGetPhysicalDeviceProperties2(physical_, &properties2);
      hostImportAlignment_ = host.minImportedHostPointerAlignment;
    }
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = static_cast<uint32_t>(deviceExtensions.size());
    deviceInfo.ppEnabledExtensionNames = deviceExtensions.data();
    VK_CHECK(vkCreateDevice(physical_, &deviceInfo, nullptr, &device_));
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = queueFamily_;
    VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &pool_));
  } catch (...) {
    release();
    throw;
  }
}

Context::~Context() {
  release();
}

void Context::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  device_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
}

void Context::pickDevice(const ContextOptions& options) {
  uint32_t count = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
  if (count == 0)
    throw ResourceError(
        "no Vulkan device found (install a driver, e.g. Debian's mesa-vulkan-drivers for "
        "lavapipe)");
  std::vector<VkPhysicalDevice> physical(count);
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, physical.data()));
  for (unsigned i = 0; i < count; ++i) {
    DeviceSummary summary{i, "", VK_PHYSICAL_DEVICE_TYPE_OTHER, {}};
    vkGetPhysicalDeviceProperties(physical[i], &summary.properties);
    summary.name = summary.properties.deviceName;
    summary.type = summary.properties.deviceType;
    devices_.push_back(summary);
  }

  if (options.deviceIndex) {
    if (*options.deviceIndex >= count)
      throw UsageError("--device: expected a device index in [0, " + std::to_string(count - 1) +
                       "], got " + std::to_string(*options.deviceIndex) + " (see 'lava info')");
    deviceIndex_ = *options.deviceIndex;
  } else if (const char* env = std::getenv("LAVA_DEVICE"); env && *env) {
    deviceIndex_ = parseDeviceIndex("LAVA_DEVICE", env, count);
  } else {
    deviceIndex_ =
        static_cast<unsigned>(std::min_element(devices_.begin(), devices_.end(),
                                               [](const DeviceSummary& a, const DeviceSummary& b) {
                                                 return typeRank(a.type) < typeRank(b.type);
                                               }) -
                              devices_.begin());
  }
  physical_ = physical[deviceIndex_];
  properties_ = devices_[deviceIndex_].properties;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  VkPhysicalDeviceMaintenance3Properties maintenance3{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties2.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(physical_, &properties2);
  VkDeviceSize largestHeap = 0;
  for (uint32_t i = 0; i < memory_.memoryHeapCount; ++i)
    if (memory_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      largestHeap = std::max(largestHeap, memory_.memoryHeaps[i].size);
  maxAllocation_ = std::min(maintenance3.maxMemoryAllocationSize, largestHeap);
  deviceMemory_ = largestHeap;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags wanted) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & wanted) == wanted)
      return i;
  throw ResourceError("no Vulkan memory type with the needed properties on this device");
}

VkCommandBuffer Context::beginOneShot() const {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &commands));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(commands, &begin));
  return commands;
}

void Context::submitAndWait(VkCommandBuffer commands) const {
  VK_CHECK(vkEndCommandBuffer(commands));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence rawFence = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFence(device_, &fenceInfo, nullptr, &rawFence));
  UniqueFence fence(device_, rawFence);
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  VK_CHECK(vkQueueSubmit(queue_, 1, &submit, fence));
  VK_CHECK(vkWaitForFences(device_, 1, &rawFence, VK_TRUE, UINT64_MAX));
  vkFreeCommandBuffers(device_, pool_, 1, &commands);
}

std::vector<std::string> Context::takeValidationMessages() {
  std::lock_guard<std::mutex> lock(messagesMutex_);
  return std::exchange(messages_, {});
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* self) {
  auto* context = static_cast<Context*>(self);
  std::lock_guard<std::mutex> lock(context->messagesMutex_);
  context->messages_.emplace_back(data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

}  // namespace lava
