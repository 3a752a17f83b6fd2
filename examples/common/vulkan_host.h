// The host's side of docs/library.md, shared by examples/embed, examples/renderpass and the
// embedding tests: what a host makes with plain Vulkan before it hands Lava its handles (an
// instance with the validation layer when installed, a device with what Lava asks for, a
// queue), and its own images, read-back buffers and frames in flight. Lava creates none of
// it and destroys none of it. Header-only; every failure throws std::runtime_error.
#pragma once
#include <lava/lava.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace vkhost {

inline void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw std::runtime_error(std::string(what) + " failed: " + lava::resultName(result));
}

inline bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

inline uint32_t memoryType(VkPhysicalDevice physical, uint32_t bits, VkMemoryPropertyFlags wanted) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory);
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  throw std::runtime_error("no suitable memory type");
}

// Memory for what `needs` describes, of a type with `wanted`.
inline VkDeviceMemory allocate(const lava::DeviceHandles& host, const VkMemoryRequirements& needs,
                               VkMemoryPropertyFlags wanted) {
  const VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, needs.size,
                                  memoryType(host.physicalDevice, needs.memoryTypeBits, wanted)};
  VkDeviceMemory memory = VK_NULL_HANDLE;
  check(vkAllocateMemory(host.device, &info, nullptr, &memory), "vkAllocateMemory");
  return memory;
}

struct DeviceOptions {
  const char* name = "host";                    // VkApplicationInfo's, and the notes' prefix
  uint32_t apiVersion = VK_API_VERSION_1_3;     // the host's (VkApplicationInfo::apiVersion)
  bool requireValidation = false;               // fail when the layer is not installed
  // Count the layer's general messages too (a test that fails on any); else they are notes.
  bool countGeneral = false;
  std::vector<const char*> instanceExtensions;  // beside debug utils, e.g. GLFW's
  std::vector<const char*> deviceExtensions;    // beside Lava's, e.g. the swapchain
  bool dynamicRendering = true;                 // false: a host that draws only in render passes
  // Lava's optional features where offered: 64-bit atomics and push descriptors, told to
  // Lava in `handles`.
  bool optionalFeatures = false;
  // Whether a queue family must also present (e.g. glfwGetPhysicalDevicePresentationSupport).
  std::function<bool(VkInstance, VkPhysicalDevice, uint32_t)> presents;
};

// The host's instance, device and queue, and the validation layer's messages. `handles` is
// what Lava is given; the host destroys it all, after Lava's objects.
class Device {
 public:
  explicit Device(const DeviceOptions& options = {})
      : name_(options.name), countGeneral_(options.countGeneral) {
    validation = options.requireValidation || hasLayer("VK_LAYER_KHRONOS_validation");
    createInstance(options);
    try {
      pickQueue(options);
      createDevice(options);
    } catch (...) {  // no destructor runs for a constructor that throws
      destroyInstance();
      throw;
    }
  }
  ~Device() {
    vkDestroyDevice(handles.device, nullptr);
    destroyInstance();
  }
  Device(const Device&) = delete;  // the messenger holds its address
  Device& operator=(const Device&) = delete;

  // The layer's messages so far, one each (the layer may call from any thread).
  std::vector<std::string> messages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
  }
  void clearMessages() {
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.clear();
  }

  lava::DeviceHandles handles;  // instance, physical device, device, queue, features
  bool validation = false;      // the layer is on, with synchronization validation

 private:
  void destroyInstance() {
    if (messenger_)
      reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(handles.instance, "vkDestroyDebugUtilsMessengerEXT"))(
          handles.instance, messenger_, nullptr);
    vkDestroyInstance(handles.instance, nullptr);
  }

  // The loader's own notices (general messages, such as "VK_INSTANCE_LAYERS ... adding
  // layers") are shown, not counted, unless asked: they say how the instance was made, not
  // that Lava misused Vulkan.
  static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT type,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* self) {
    Device& host = *static_cast<Device*>(self);
    if (!(type & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT) && !host.countGeneral_) {
      std::fprintf(stderr, "%s: note: %s\n", host.name_, data->pMessage);
      return VK_FALSE;
    }
    std::lock_guard<std::mutex> lock(host.mutex_);
    host.messages_.emplace_back(data->pMessage);
    return VK_FALSE;
  }

  void createInstance(const DeviceOptions& options) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = options.name;
    app.apiVersion = options.apiVersion;
    std::vector<const char*> extensions = options.instanceExtensions;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    VkDebugUtilsMessengerCreateInfoEXT debug{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    debug.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    debug.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    debug.pfnUserCallback = &onMessage;
    debug.pUserData = this;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    if (validation) {
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
      debug.pNext = &features;  // the messenger also hears the instance's creation
      info.pNext = &debug;
      info.enabledLayerCount = 1;
      info.ppEnabledLayerNames = &layer;
    }
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    check(vkCreateInstance(&info, nullptr, &handles.instance), "vkCreateInstance");
    if (!validation) return;
    debug.pNext = nullptr;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(handles.instance, "vkCreateDebugUtilsMessengerEXT"));
    check(create(handles.instance, &debug, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }

  // The first device, and its first family that draws, computes and (when asked) presents.
  void pickQueue(const DeviceOptions& options) {
    uint32_t count = 1;
    const VkResult listed =
        vkEnumeratePhysicalDevices(handles.instance, &count, &handles.physicalDevice);
    if (listed != VK_INCOMPLETE) check(listed, "vkEnumeratePhysicalDevices");
    if (count == 0) throw std::runtime_error("no Vulkan device");
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(handles.physicalDevice, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(handles.physicalDevice, &families, props.data());
    const VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    uint32_t& family = handles.queueFamily;
    for (family = 0; family < families; ++family)
      if ((props[family].queueFlags & needed) == needed &&
          (!options.presents || options.presents(handles.instance, handles.physicalDevice, family)))
        return;
    throw std::runtime_error(options.presents ? "no queue that draws, computes and presents"
                                              : "no queue that draws and computes");
  }

  // What Lava needs, asked of Lava (deviceRequirements), and its optional features where
  // the device offers them.
  void createDevice(const DeviceOptions& options) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(handles.physicalDevice, &properties);
    const lava::DeviceRequirements needs =
        lava::deviceRequirements(std::min(options.apiVersion, properties.apiVersion));
    VkPhysicalDeviceDynamicRenderingFeatures dynamic{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
    dynamic.dynamicRendering = options.dynamicRendering;  // needs.dynamicRendering, unless passes
    VkPhysicalDeviceShaderAtomicInt64Features atomics{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES};
    if (options.optionalFeatures && needs.int64Atomics) {
      VkPhysicalDeviceFeatures2 offered{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
      offered.pNext = &atomics;
      vkGetPhysicalDeviceFeatures2(handles.physicalDevice, &offered);
      handles.int64Atomics = offered.features.shaderInt64 && atomics.shaderBufferInt64Atomics;
    }
    VkPhysicalDeviceFeatures2 enabled{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    enabled.features.shaderInt64 = handles.int64Atomics;
    atomics.pNext = nullptr;
    atomics.shaderBufferInt64Atomics = handles.int64Atomics;
    // The dynamic-rendering structure only when it is asked for (on 1.2 its extension is).
    void** tail = &enabled.pNext;
    if (options.dynamicRendering) {
      *tail = &dynamic;
      tail = &dynamic.pNext;
    }
    if (handles.int64Atomics) *tail = &atomics;
    handles.dynamicRendering = options.dynamicRendering;

    std::vector<const char*> extensions = needs.extensions;
    if (!options.dynamicRendering)  // on 1.2 it is the extension; not asked for, not enabled
      extensions.erase(std::remove_if(extensions.begin(), extensions.end(),
                                      [](const char* e) {
                                        return std::strcmp(e, "VK_KHR_dynamic_rendering") == 0;
                                      }),
                       extensions.end());
    extensions.insert(extensions.end(), options.deviceExtensions.begin(),
                      options.deviceExtensions.end());
    if (options.optionalFeatures) addOffered(needs, extensions);
    handles.pushDescriptors =
        std::any_of(extensions.begin(), extensions.end(), [](const char* e) {
          return std::strcmp(e, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME) == 0;
        });

    const float priority = 1.0f;
    const VkDeviceQueueCreateInfo queue{
        VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, nullptr, 0, handles.queueFamily, 1, &priority};
    const VkDeviceCreateInfo info{
        VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,     &enabled,          0,      1, &queue, 0, nullptr,
        static_cast<uint32_t>(extensions.size()), extensions.data(), nullptr};
    check(vkCreateDevice(handles.physicalDevice, &info, nullptr, &handles.device),
          "vkCreateDevice");
    vkGetDeviceQueue(handles.device, handles.queueFamily, 0, &handles.queue);
  }

  // Lava's optional extensions that the device offers, added.
  void addOffered(const lava::DeviceRequirements& needs, std::vector<const char*>& extensions) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(handles.physicalDevice, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> offered(count);
    vkEnumerateDeviceExtensionProperties(handles.physicalDevice, nullptr, &count, offered.data());
    for (const char* optional : needs.optionalExtensions)
      for (const VkExtensionProperties& e : offered)
        if (std::strcmp(e.extensionName, optional) == 0) extensions.push_back(optional);
  }

  const char* name_;
  bool countGeneral_;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

// The host's own 2D image in device-local memory, and its view.
class Image {
 public:
  Image(const lava::DeviceHandles& host, VkExtent2D extent, VkFormat format,
        VkImageUsageFlags usage, VkImageAspectFlags aspect)
      : device_(host.device) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    check(vkCreateImage(device_, &info, nullptr, &image), "vkCreateImage");
    VkMemoryRequirements needs;
    vkGetImageMemoryRequirements(device_, image, &needs);
    memory_ = allocate(host, needs, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkBindImageMemory(device_, image, memory_, 0), "vkBindImageMemory");
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
    check(vkCreateImageView(device_, &viewInfo, nullptr, &view), "vkCreateImageView");
  }
  ~Image() {
    vkDestroyImageView(device_, view, nullptr);
    vkDestroyImage(device_, image, nullptr);
    vkFreeMemory(device_, memory_, nullptr);
  }
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;

 private:
  VkDevice device_;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
};

// A host-visible, coherent buffer the host copies into and reads.
class Readback {
 public:
  Readback(const lava::DeviceHandles& host, VkDeviceSize bytes)
      : device_(host.device), bytes_(bytes) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    check(vkCreateBuffer(device_, &info, nullptr, &buffer), "vkCreateBuffer");
    VkMemoryRequirements needs;
    vkGetBufferMemoryRequirements(device_, buffer, &needs);
    memory_ = allocate(host, needs,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    check(vkBindBufferMemory(device_, buffer, memory_, 0), "vkBindBufferMemory");
  }
  ~Readback() {
    vkDestroyBuffer(device_, buffer, nullptr);
    vkFreeMemory(device_, memory_, nullptr);
  }
  Readback(const Readback&) = delete;
  Readback& operator=(const Readback&) = delete;

  // Once the copy into it has finished (and a barrier made it visible to the host).
  std::vector<uint8_t> read() const {
    void* mapped = nullptr;
    check(vkMapMemory(device_, memory_, 0, bytes_, 0, &mapped), "vkMapMemory");
    const auto* bytes = static_cast<const uint8_t*>(mapped);
    std::vector<uint8_t> out(bytes, bytes + bytes_);
    vkUnmapMemory(device_, memory_);
    return out;
  }

  VkBuffer buffer = VK_NULL_HANDLE;

 private:
  VkDevice device_;
  VkDeviceSize bytes_;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
};

// The host's frames in flight: a command buffer and a fence each, the fence's index being
// the slot Lava is told (docs/library.md).
class Frames {
 public:
  Frames(const lava::DeviceHandles& host, uint32_t count)
      : device_(host.device), queue_(host.queue), commands_(count), fences_(count) {
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = host.queueFamily;
    check(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.commandBufferCount = count;
    check(vkAllocateCommandBuffers(device_, &alloc, commands_.data()), "vkAllocateCommandBuffers");
    for (VkFence& fence : fences_) {
      VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      check(vkCreateFence(device_, &info, nullptr, &fence), "vkCreateFence");
    }
  }
  ~Frames() {
    vkDeviceWaitIdle(device_);
    for (VkFence fence : fences_) vkDestroyFence(device_, fence, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
  }
  Frames(const Frames&) = delete;
  Frames& operator=(const Frames&) = delete;

  // Until `slot`'s last frame has finished.
  void wait(uint32_t slot) const {
    check(vkWaitForFences(device_, 1, &fences_[slot], VK_TRUE, UINT64_MAX), "vkWaitForFences");
  }
  // Waits for `slot`'s last frame, then begins its command buffer.
  VkCommandBuffer begin(uint32_t slot) {
    wait(slot);
    check(vkResetFences(device_, 1, &fences_[slot]), "vkResetFences");
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    check(vkBeginCommandBuffer(commands_[slot], &info), "vkBeginCommandBuffer");
    return commands_[slot];
  }
  // Ends and submits `slot`'s command buffer, signalling its fence; `wait` (at `stage`) and
  // `signal` are the presentation's semaphores, when there is one.
  void submit(uint32_t slot, VkSemaphore wait = VK_NULL_HANDLE,
              VkPipelineStageFlags stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
              VkSemaphore signal = VK_NULL_HANDLE) {
    check(vkEndCommandBuffer(commands_[slot]), "vkEndCommandBuffer");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = wait ? 1 : 0;
    submit.pWaitSemaphores = &wait;
    submit.pWaitDstStageMask = &stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commands_[slot];
    submit.signalSemaphoreCount = signal ? 1 : 0;
    submit.pSignalSemaphores = &signal;
    check(vkQueueSubmit(queue_, 1, &submit, fences_[slot]), "vkQueueSubmit");
  }

 private:
  VkDevice device_;
  VkQueue queue_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::vector<VkCommandBuffer> commands_;
  std::vector<VkFence> fences_;
};

// One image barrier, as the frame recipe's transitions between Lava's calls are written.
inline void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                         VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
                         VkAccessFlags srcAccess, VkPipelineStageFlags dstStage,
                         VkAccessFlags dstAccess) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = srcAccess;
  b.dstAccessMask = dstAccess;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

// How many of the slots are equal bit for bit (a host's own check of Lava's determinism;
// Lava::lava_tools's lava::compare also names the first difference).
inline uint64_t identicalSlots(const std::vector<lava::Particle>& a,
                               const std::vector<lava::Particle>& b) {
  if (a.size() != b.size()) return 0;
  uint64_t equal = 0;
  for (size_t i = 0; i < a.size(); ++i)
    equal += std::memcmp(&a[i], &b[i], sizeof(lava::Particle)) == 0;
  return equal;
}

}  // namespace vkhost
