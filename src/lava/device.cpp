// lava::Device: Lava's own instance and device, or the host's borrowed handles, described
// once into a DeviceContext that every other Lava object works from.
#include "lava/device.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include "common/check.h"
#include "lava/error.h"
#include "shared.h"
#include "vulkan/device_context.h"

namespace lava {
namespace detail {

bool DeviceContext::hasExtension(const char* name) const {
  return std::find(extensions.begin(), extensions.end(), name) != extensions.end();
}

uint32_t DeviceContext::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                       VkMemoryPropertyFlags preferred) const {
  for (VkMemoryPropertyFlags wanted : {required | preferred, required})
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
      if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted)
        return i;
  throw ResourceError("no Vulkan memory type with the needed properties on this device");
}

VkCommandBuffer DeviceContext::beginOneShot() const {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  VK_CHECK(vk.AllocateCommandBuffers(device(), &alloc, &commands));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const VkResult began = vk.BeginCommandBuffer(commands, &begin);
  if (began != VK_SUCCESS) {
    vk.FreeCommandBuffers(device(), pool, 1, &commands);
    VK_CHECK_RESULT(began, "vkBeginCommandBuffer");
  }
  return commands;
}

void DeviceContext::submitAndWait(VkCommandBuffer commands) const {
  struct Free {  // the command buffer goes back to the pool however this ends
    const DeviceContext& c;
    VkCommandBuffer commands;
    ~Free() { c.vk.FreeCommandBuffers(c.device(), c.pool, 1, &commands); }
  } free{*this, commands};
  VK_CHECK(vk.EndCommandBuffer(commands));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VK_CHECK(vk.CreateFence(device(), &fenceInfo, allocator(), &fence));
  struct DestroyFence {
    const DeviceContext& c;
    VkFence fence;
    ~DestroyFence() { c.vk.DestroyFence(c.device(), fence, c.allocator()); }
  } destroy{*this, fence};
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  VK_CHECK(vk.QueueSubmit(handles.queue, 1, &submit, fence));
  const VkResult waited = vk.WaitForFences(device(), 1, &fence, VK_TRUE, UINT64_MAX);
  if (waited != VK_SUCCESS) {
    // The work may still run: nothing it uses is freed before the device is idle (or lost).
    vk.DeviceWaitIdle(device());
    VK_CHECK_RESULT(waited, "vkWaitForFences");
  }
}

void DeviceContext::describe() {
  VkPhysicalDevice physical = handles.physicalDevice;
  pushDescriptors = handles.pushDescriptors;
  if (pushDescriptors && !vk.CmdPushDescriptorSetKHR)
    throw ResourceError("the Vulkan driver does not provide vkCmdPushDescriptorSetKHR");
  vk.GetPhysicalDeviceProperties(physical, &properties);
  vk.GetPhysicalDeviceMemoryProperties(physical, &memory);
  VkPhysicalDeviceMaintenance3Properties maintenance3{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  driver = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  floatControls = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES};
  maintenance3.pNext = &driver;
  driver.pNext = &floatControls;
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties2.pNext = &maintenance3;
  vk.GetPhysicalDeviceProperties2(physical, &properties2);
  driver.pNext = nullptr;
  floatControls.pNext = nullptr;
  limits = properties.limits;
  VkDeviceSize largestHeap = 0;
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      largestHeap = std::max(largestHeap, memory.memoryHeaps[i].size);
  maxAllocation = std::min(maintenance3.maxMemoryAllocationSize, largestHeap);
  deviceLocal = largestHeap;
}

void DeviceContext::createPool() {
  VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  info.queueFamilyIndex = handles.queueFamily;
  VK_CHECK(vk.CreateCommandPool(device(), &info, allocator(), &pool));
}

void DeviceContext::release() {
  if (handles.device && pool) vk.DestroyCommandPool(handles.device, pool, allocator());
  pool = VK_NULL_HANDLE;
  if (!owned) return;
  if (handles.device) vk.DestroyDevice(handles.device, nullptr);
  if (messenger) vk.DestroyDebugUtilsMessengerEXT(handles.instance, messenger, nullptr);
  if (handles.instance) vk.DestroyInstance(handles.instance, nullptr);
  handles = {};
  messenger = VK_NULL_HANDLE;
}

}  // namespace detail

namespace {

using detail::DeviceContext;

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::vector<VkExtensionProperties> deviceExtensions(const detail::Vk& vk,
                                                    VkPhysicalDevice physical) {
  uint32_t count = 0;
  VK_CHECK(vk.EnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  VK_CHECK(vk.EnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data()));
  extensions.resize(count);
  return extensions;
}

bool offers(const std::vector<VkExtensionProperties>& extensions, const char* name) {
  return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
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

// The first queue family with graphics and compute, if any.
std::optional<uint32_t> queueFamilyOf(const detail::Vk& vk, VkPhysicalDevice physical) {
  uint32_t count = 0;
  vk.GetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vk.GetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
  const VkQueueFlags both = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & both) == both) return i;
  return std::nullopt;
}

// Whether `physical` offers shaderInt64 and shaderBufferInt64Atomics, asked with Vulkan 1.0
// calls only (any instance): a device that offers VK_KHR_shader_atomic_int64 must support
// shaderBufferInt64Atomics.
bool offersInt64AtomicsOn10(const detail::Vk& vk, VkPhysicalDevice physical) {
  VkPhysicalDeviceFeatures features;
  vk.GetPhysicalDeviceFeatures(physical, &features);
  return features.shaderInt64 &&
         offers(deviceExtensions(vk, physical), VK_KHR_SHADER_ATOMIC_INT64_EXTENSION_NAME);
}

// The same, asked of Vulkan 1.2 (where the extension is core and need not be listed).
bool offersInt64Atomics(const detail::Vk& vk, VkPhysicalDevice physical) {
  VkPhysicalDeviceShaderAtomicInt64Features atomics{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &atomics;
  vk.GetPhysicalDeviceFeatures2(physical, &features);
  return features.features.shaderInt64 && atomics.shaderBufferInt64Atomics;
}

// Why `physical` cannot run Lava, or empty when it can; `dynamicRendering`: whether the
// path Lava draws on needs it (a host that draws only in render passes may do without).
std::string unsuitability(const detail::Vk& vk, VkPhysicalDevice physical,
                          bool dynamicRendering = true) {
  VkPhysicalDeviceProperties properties;
  vk.GetPhysicalDeviceProperties(physical, &properties);
  const std::string name = std::string("device '") + properties.deviceName + "'";
  if (properties.apiVersion < VK_API_VERSION_1_2) return name + " supports only Vulkan 1.0/1.1";
  if (!queueFamilyOf(vk, physical)) return name + " has no queue with both graphics and compute";
  if (!dynamicRendering) return {};
  const std::vector<VkExtensionProperties> extensions = deviceExtensions(vk, physical);
  for (const char* required : deviceRequirements(properties.apiVersion).extensions)
    if (!offers(extensions, required))
      return name + " lacks " + required +
             " for dynamic rendering (a host that draws only in render passes clears "
             "DeviceHandles::dynamicRendering)";
  VkPhysicalDeviceDynamicRenderingFeatures dynamic{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &dynamic;
  vk.GetPhysicalDeviceFeatures2(physical, &features);
  if (!dynamic.dynamicRendering) {
    // Every Vulkan 1.3 device has it: the instance hides it, made for an older version.
    if (properties.apiVersion >= VK_API_VERSION_1_3)
      return name + " is Vulkan 1.3, but the instance was created for an older version " +
             "(VkApplicationInfo::apiVersion; without application info it is 1.0), which " +
             "hides dynamic rendering: Lava needs an instance of Vulkan 1.3, or of 1.2 with " +
             "VK_KHR_dynamic_rendering enabled on the device";
    return name + " lacks dynamic rendering (a host that draws only in render passes clears " +
           "DeviceHandles::dynamicRendering)";
  }
  return {};
}

// Lava's instance version, checked before any call where the host gives it.
void checkInstanceVersion(uint32_t apiVersion) {
  if (apiVersion == 0 || apiVersion >= VK_API_VERSION_1_2) return;
  throw InvalidArgument("VkApplicationInfo::apiVersion",
                        "the instance is Vulkan " +
                            std::to_string(VK_API_VERSION_MAJOR(apiVersion)) + "." +
                            std::to_string(VK_API_VERSION_MINOR(apiVersion)) +
                            ", which hides what Lava needs of the device: create it with "
                            "VK_API_VERSION_1_3 (or 1.2 with VK_KHR_dynamic_rendering on the "
                            "device)");
}

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                         VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                         void* user) {
  auto* context = static_cast<DeviceContext*>(user);
  std::lock_guard<std::mutex> lock(context->messagesMutex);
  context->messages.emplace_back(data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

// ResourceError unless the validation layer is installed.
void checkValidationLayer(const detail::Vk& vk) {
  uint32_t count = 0;
  VK_CHECK(vk.EnumerateInstanceLayerProperties(&count, nullptr));
  std::vector<VkLayerProperties> layers(count);
  VK_CHECK(vk.EnumerateInstanceLayerProperties(&count, layers.data()));
  if (!std::any_of(layers.begin(), layers.end(), [](const VkLayerProperties& l) {
        return std::strcmp(l.layerName, kValidationLayer) == 0;
      }))
    throw ResourceError(
        "the Vulkan validation layer is not installed (Debian: vulkan-validationlayers)");
}

void createInstance(DeviceContext& c, const DeviceOptions& options) {
  detail::Vk& vk = c.vk;
  uint32_t count = 0;
  VK_CHECK(vk.EnumerateInstanceExtensionProperties(nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> available(count);
  VK_CHECK(vk.EnumerateInstanceExtensionProperties(nullptr, &count, available.data()));
  available.resize(count);
  if (options.validation) checkValidationLayer(vk);

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = options.applicationName.c_str();
  app.pEngineName = "lava";
  app.apiVersion = VK_API_VERSION_1_3;
  std::vector<const char*> extensions = options.instanceExtensions;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  // Portability drivers (MoltenVK) are listed only when the application says it knows them.
  if (offers(available, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    info.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  }
  VkDebugUtilsMessengerCreateInfoEXT messenger{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &onMessage;
  messenger.pUserData = &c;
  VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  if (options.validation) {
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    messenger.pNext = &features;
    info.pNext = &messenger;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &kValidationLayer;
  }
  info.pApplicationInfo = &app;
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  const VkResult created = vk.CreateInstance(&info, nullptr, &c.handles.instance);
  if (created == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw ResourceError(
        "no Vulkan driver found (install one, e.g. Debian's mesa-vulkan-drivers for lavapipe)");
  VK_CHECK_RESULT(created, "vkCreateInstance");
  vk.loadInstance(c.handles.instance);
  if (options.validation) {
    messenger.pNext = nullptr;
    VK_CHECK(
        vk.CreateDebugUtilsMessengerEXT(c.handles.instance, &messenger, nullptr, &c.messenger));
  }
}

void pickPhysicalDevice(DeviceContext& c, const DeviceOptions& options) {
  const detail::Vk& vk = c.vk;
  uint32_t count = 0;
  VK_CHECK(vk.EnumeratePhysicalDevices(c.handles.instance, &count, nullptr));
  if (count == 0)
    throw ResourceError(
        "no Vulkan device found (install a driver, e.g. Debian's mesa-vulkan-drivers for "
        "lavapipe)");
  std::vector<VkPhysicalDevice> physical(count);
  VK_CHECK(vk.EnumeratePhysicalDevices(c.handles.instance, &count, physical.data()));
  for (unsigned i = 0; i < count; ++i) {
    VkPhysicalDeviceProperties p;
    vk.GetPhysicalDeviceProperties(physical[i], &p);
    c.candidates.push_back({i, p.deviceName, p.deviceType, p.apiVersion});
  }
  if (options.index) {
    if (*options.index >= count)
      throw InvalidArgument("device", "expected a device index in [0, " +
                                          std::to_string(count - 1) + "], got " +
                                          std::to_string(*options.index));
    c.index = *options.index;
    const std::string why = unsuitability(vk, physical[c.index]);
    if (!why.empty()) throw ResourceError(why + ": it cannot run Lava");
  } else {
    int best = 5;
    std::string why;
    for (unsigned i = 0; i < count; ++i) {
      const std::string problem = unsuitability(vk, physical[i]);
      if (!problem.empty()) {
        why = problem;
        continue;
      }
      if (typeRank(c.candidates[i].type) < best) {
        best = typeRank(c.candidates[i].type);
        c.index = i;
      }
    }
    if (best == 5) throw ResourceError("no Vulkan device can run Lava (" + why + ")");
  }
  c.handles.physicalDevice = physical[c.index];
}

void createLogicalDevice(DeviceContext& c, const DeviceOptions& options) {
  detail::Vk& vk = c.vk;
  VkPhysicalDevice physical = c.handles.physicalDevice;
  c.handles.queueFamily = *queueFamilyOf(vk, physical);
  VkPhysicalDeviceProperties properties;
  vk.GetPhysicalDeviceProperties(physical, &properties);
  const std::vector<VkExtensionProperties> offered = deviceExtensions(vk, physical);
  std::vector<const char*> enabled = deviceRequirements(properties.apiVersion).extensions;
  for (const char* wanted : options.deviceExtensions)
    if (offers(offered, wanted)) enabled.push_back(wanted);
  // A portability driver's subset must be enabled where it is offered.
  if (offers(offered, "VK_KHR_portability_subset")) enabled.push_back("VK_KHR_portability_subset");
  c.handles.pushDescriptors =
      options.pushDescriptors && offers(offered, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
  if (c.handles.pushDescriptors) enabled.push_back(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
  for (const char* e : enabled) c.extensions.emplace_back(e);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = c.handles.queueFamily;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkPhysicalDeviceDynamicRenderingFeatures dynamic{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
  dynamic.dynamicRendering = VK_TRUE;
  // Optional: 64-bit buffer atomics, for the splat's pairs of pixels.
  VkPhysicalDeviceShaderAtomicInt64Features atomics{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &dynamic;
  c.handles.int64Atomics = options.int64Atomics && offersInt64Atomics(vk, physical);
  if (c.handles.int64Atomics) {
    atomics.shaderBufferInt64Atomics = VK_TRUE;
    features.features.shaderInt64 = VK_TRUE;
    dynamic.pNext = &atomics;
  }
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = static_cast<uint32_t>(enabled.size());
  info.ppEnabledExtensionNames = enabled.data();
  VK_CHECK(vk.CreateDevice(physical, &info, nullptr, &c.handles.device));
  vk.loadDevice(c.handles.device);
  vk.GetDeviceQueue(c.handles.device, c.handles.queueFamily, 0, &c.handles.queue);
}

}  // namespace

DeviceRequirements deviceRequirements(uint32_t deviceApiVersion) {
  DeviceRequirements r;
  r.instanceApiVersion = VK_API_VERSION_1_2;
  r.dynamicRendering = true;
  r.int64Atomics = true;
  r.optionalExtensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  if (deviceApiVersion < VK_API_VERSION_1_3)
    r.extensions.push_back(VK_KHR_DYNAMIC_RENDERING_EXTENSION_NAME);
  return r;
}

DeviceRequirements deviceRequirements(VkInstance instance, VkPhysicalDevice physical,
                                      PFN_vkGetInstanceProcAddr getInstanceProcAddr,
                                      uint32_t instanceApiVersion) {
  checkInstanceVersion(instanceApiVersion);
  detail::Vk vk;
  vk.loadGlobal(getInstanceProcAddr ? getInstanceProcAddr : vkGetInstanceProcAddr);
  vk.loadInstance(instance);
  VkPhysicalDeviceProperties properties;
  vk.GetPhysicalDeviceProperties(physical, &properties);
  DeviceRequirements r = deviceRequirements(properties.apiVersion);
  // Vulkan 1.0 calls only, unless the host says its instance is of 1.2 or later.
  r.int64Atomics = instanceApiVersion >= VK_API_VERSION_1_2 ? offersInt64Atomics(vk, physical)
                                                            : offersInt64AtomicsOn10(vk, physical);
  const std::vector<VkExtensionProperties> offered = deviceExtensions(vk, physical);
  std::vector<const char*> optional;
  for (const char* name : r.optionalExtensions)
    if (offers(offered, name)) optional.push_back(name);
  r.optionalExtensions = optional;
  return r;
}

namespace {

// Whether a structure of `type` (a T) in the chain from `next` has `feature` on: the host
// may enable a feature through its core structure or its extension's, in any order.
template <typename T>
bool chainEnables(const void* next, VkStructureType type, VkBool32 T::*feature) {
  for (auto* s = static_cast<const VkBaseInStructure*>(next); s; s = s->pNext)
    if (s->sType == type && reinterpret_cast<const T*>(s)->*feature) return true;
  return false;
}

// The features a borrowed device was created with, as the host gave them: what Lava needs
// must be there (InvalidArgument naming the feature).
void checkEnabledFeatures(const DeviceHandles& h, uint32_t apiVersion) {
  if (!h.enabledFeatures) return;
  const void* chain = h.enabledFeatures->pNext;
  const bool dynamicRendering =
      chainEnables(chain, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
                   &VkPhysicalDeviceVulkan13Features::dynamicRendering) ||
      chainEnables(chain, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES,
                   &VkPhysicalDeviceDynamicRenderingFeatures::dynamicRendering);
  const bool atomics =
      chainEnables(chain, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                   &VkPhysicalDeviceVulkan12Features::shaderBufferInt64Atomics) ||
      chainEnables(chain, VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES,
                   &VkPhysicalDeviceShaderAtomicInt64Features::shaderBufferInt64Atomics);
  if (h.dynamicRendering && !dynamicRendering)
    throw InvalidArgument(
        "enabledFeatures",
        std::string("the device was created without dynamicRendering (") +
            (apiVersion >= VK_API_VERSION_1_3 ? "VkPhysicalDeviceVulkan13Features"
                                              : "VkPhysicalDeviceDynamicRenderingFeatures") +
            "), but DeviceHandles::dynamicRendering is set: enable it, or "
            "clear the flag and give Lava render passes");
  if (h.int64Atomics && !h.enabledFeatures->features.shaderInt64)
    throw InvalidArgument("int64Atomics",
                          "set, but the device was created without shaderInt64 "
                          "(VkPhysicalDeviceFeatures)");
  if (h.int64Atomics && !atomics)
    throw InvalidArgument("int64Atomics",
                          "set, but the device was created without shaderBufferInt64Atomics "
                          "(VkPhysicalDeviceVulkan12Features or "
                          "VkPhysicalDeviceShaderAtomicInt64Features)");
}

}  // namespace

namespace {

uint32_t checkedFramesInFlight(uint32_t count) {
  if (count < 1 || count > 16)
    throw InvalidArgument("framesInFlight", "expected 1 to 16, got " + std::to_string(count));
  return count;
}

}  // namespace

Device::Device(const DeviceOptions& options) : context_(std::make_unique<DeviceContext>()) {
  DeviceContext& c = *context_;
  c.owned = true;
  c.framesInFlight = checkedFramesInFlight(options.framesInFlight);
  c.vk.loadGlobal(vkGetInstanceProcAddr);
  try {
    createInstance(c, options);
    pickPhysicalDevice(c, options);
    createLogicalDevice(c, options);
    c.handles.getInstanceProcAddr = vkGetInstanceProcAddr;
    c.describe();
    if (!options.floatControls) {
      c.floatControls.shaderRoundingModeRTEFloat32 = VK_FALSE;
      c.floatControls.shaderSignedZeroInfNanPreserveFloat32 = VK_FALSE;
    }
    c.createPool();
  } catch (...) {
    c.release();
    throw;
  }
}

Device::Device(const DeviceHandles& borrowed) : context_(std::make_unique<DeviceContext>()) {
  DeviceContext& c = *context_;
  if (!borrowed.instance || !borrowed.physicalDevice || !borrowed.device || !borrowed.queue)
    throw InvalidArgument("handles", "instance, physical device, device and queue are required");
  checkInstanceVersion(borrowed.instanceApiVersion);
  c.handles = borrowed;
  c.framesInFlight = checkedFramesInFlight(borrowed.framesInFlight);
  if (!c.handles.getInstanceProcAddr) c.handles.getInstanceProcAddr = vkGetInstanceProcAddr;
  c.vk.loadGlobal(c.handles.getInstanceProcAddr);
  c.vk.loadInstance(c.handles.instance);
  const std::string why = unsuitability(c.vk, c.handles.physicalDevice, borrowed.dynamicRendering);
  if (!why.empty()) throw ResourceError(why + ": it cannot run Lava");
  if (borrowed.int64Atomics && !offersInt64Atomics(c.vk, c.handles.physicalDevice))
    throw InvalidArgument("int64Atomics",
                          "set, but the device offers no shaderInt64 or shaderBufferInt64Atomics");
  {
    VkPhysicalDeviceProperties properties;
    c.vk.GetPhysicalDeviceProperties(c.handles.physicalDevice, &properties);
    checkEnabledFeatures(borrowed, properties.apiVersion);
    c.handles.enabledFeatures = nullptr;  // the host's, valid only in this call
  }
  const std::vector<VkExtensionProperties> offered =
      deviceExtensions(c.vk, c.handles.physicalDevice);
  if (borrowed.pushDescriptors && !offers(offered, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
    throw InvalidArgument(
        "pushDescriptors",
        "set, but the device offers no " + std::string(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME));
  c.vk.loadDevice(c.handles.device);
  for (const VkExtensionProperties& e : offered) c.extensions.emplace_back(e.extensionName);
  c.describe();
  c.createPool();
}

Device::~Device() {
  // Only Lava's own device: waiting on a borrowed one would need every queue of the host
  // externally synchronised, and the host may be using them on other threads.
  if (context_->owned && context_->handles.device)
    context_->vk.DeviceWaitIdle(context_->handles.device);
  context_->release();
}

void detail::DeviceContext::checkFrame(uint32_t frame) const {
  const uint32_t count = framesInFlight;
  if (frame >= count)
    throw InvalidArgument("frame", "frame slot " + std::to_string(frame) +
                                       " is not below the device's " + std::to_string(count) +
                                       " frames in flight: pass the index of the fence that "
                                       "guards the frame, or raise the count "
                                       "(Device::setFramesInFlight)");
}

void Device::setFramesInFlight(uint32_t count) {
  context_->framesInFlight = checkedFramesInFlight(count);
}
uint32_t Device::framesInFlight() const {
  return context_->framesInFlight;
}

const DeviceHandles& Device::handles() const {
  return context_->handles;
}
bool Device::ownsHandles() const {
  return context_->owned;
}
const VkPhysicalDeviceProperties& Device::properties() const {
  return context_->properties;
}
const VkPhysicalDeviceLimits& Device::limits() const {
  return context_->limits;
}
bool Device::hasExtension(const char* extension) const {
  return context_->hasExtension(extension);
}
VkDeviceSize Device::deviceLocalBytes() const {
  return context_->deviceLocal;
}
VkDeviceSize Device::maxAllocationBytes() const {
  return context_->maxAllocation;
}
const std::vector<DeviceSummary>& Device::candidates() const {
  return context_->candidates;
}
unsigned Device::index() const {
  return context_->index;
}

std::string Device::driver() const {
  const VkPhysicalDeviceDriverProperties& d = context_->driver;
  std::string text = d.driverName;
  if (d.driverInfo[0]) text += std::string(": ") + d.driverInfo;
  const uint32_t v = context_->properties.driverVersion;
  char version[48];
  std::snprintf(version, sizeof(version), " (driver version 0x%08x)", v);
  return text + version;
}

std::string Device::floatControls() const {
  const VkPhysicalDeviceFloatControlsProperties& f = context_->floatControls;
  auto yes = [](VkBool32 b) { return b ? "yes" : "no"; };
  return std::string("float32: RTE rounding ") + yes(f.shaderRoundingModeRTEFloat32) +
         ", signed zero/inf/nan preserved " + yes(f.shaderSignedZeroInfNanPreserveFloat32) +
         ", denormals preserved " + yes(f.shaderDenormPreserveFloat32) + ", flushed " +
         yes(f.shaderDenormFlushToZeroFloat32);
}

std::string Device::optionalPaths() const {
  const DeviceContext& c = *context_;
  auto yes = [](bool b) { return b ? "yes" : "no"; };
  return std::string("push descriptors ") +
         (c.pushDescriptors ? "yes" : "no (descriptor sets per frame slot)") + ", 64-bit atomics " +
         yes(c.handles.int64Atomics) + ", RTE declared " +
         yes(c.floatControls.shaderRoundingModeRTEFloat32) + ", signed zero declared " +
         yes(c.floatControls.shaderSignedZeroInfNanPreserveFloat32) + ", texel view " +
         std::to_string(c.limits.maxTexelBufferElements) + " texels";
}

uint32_t Device::particlesPerChunk() const {
  const VkPhysicalDeviceLimits& l = context_->limits;
  const uint64_t bytes = sizeof(Particle);
  const uint64_t perChunk = std::min<uint64_t>(
      {l.maxStorageBufferRange / bytes, context_->maxAllocation / bytes,
       uint64_t{l.maxTexelBufferElements} / 2,  // two RGBA32F texels per particle
       uint64_t{l.maxComputeWorkGroupCount[0]} * gpu::kWorkgroupSize, uint64_t{1} << 31});
  return static_cast<uint32_t>(perChunk - perChunk % gpu::kWorkgroupSize);
}

uint64_t Device::maxParticles() const {
  return std::min<uint64_t>(context_->deviceLocal / sizeof(Particle), uint64_t{1} << 31);
}

std::vector<std::string> Device::takeValidationMessages() {
  std::lock_guard<std::mutex> lock(context_->messagesMutex);
  return std::exchange(context_->messages, {});
}

void Device::waitIdle() const {
  VK_CHECK(context_->vk.DeviceWaitIdle(context_->handles.device));
}

void Device::submitNow(const std::function<void(VkCommandBuffer)>& record) const {
  context_->submitNow(record);
}

}  // namespace lava
