// A host application that embeds Lava: its own instance, device, queue, command buffers,
// colour and depth images (Lava creates none of them); Lava's simulation, backdrop, lines
// (the graphics pipeline and the splat, tested against the depth) and glow recorded into
// them by the frame recipe of docs/library.md, submitted on its own queue. It then reads
// the state back, checks it against Lava's CPU reference bit for bit, checks that the lava
// lit its image, and exits 0 when both hold with no validation message.
//
//   cmake -S examples/embed -B embed -DCMAKE_PREFIX_PATH=<where Lava is installed>
//   cmake --build embed && ./embed/lava_embed
#include <lava/lava.h>
#include <lava/validation.h>  // lava::compare
#include <vulkan/vulkan.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw std::runtime_error(std::string(what) + " failed: " + lava::resultName(result));
}

// The host's validation messages (the layer is used when it is installed). The loader's own
// notices (general messages, such as "VK_INSTANCE_LAYERS ... adding layers") are shown, not
// counted: they say how the instance was made, not that Lava misused Vulkan.
std::vector<std::string> messages;
VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                         VkDebugUtilsMessageTypeFlagsEXT type,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  if (type & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT)
    messages.emplace_back(data->pMessage);
  else
    std::fprintf(stderr, "embed: note: %s\n", data->pMessage);
  return VK_FALSE;
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

uint32_t memoryType(VkPhysicalDevice physical, uint32_t bits, VkMemoryPropertyFlags wanted) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory);
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  throw std::runtime_error("no suitable memory type");
}

struct Host {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkQueue queue = VK_NULL_HANDLE;
  bool int64Atomics = false;     // enabled: Lava's splat adds two pixels per atomic
  bool pushDescriptors = false;  // VK_KHR_push_descriptor enabled

  Host() {
    const bool validation = hasLayer("VK_LAYER_KHRONOS_validation");
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "lava_embed";
    app.apiVersion = VK_API_VERSION_1_3;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* debugUtils = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT debug{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    debug.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    debug.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    debug.pfnUserCallback = &onMessage;
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    debug.pNext = &features;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    if (validation) {
      info.pNext = &debug;
      info.enabledLayerCount = 1;
      info.ppEnabledLayerNames = &layer;
      info.enabledExtensionCount = 1;
      info.ppEnabledExtensionNames = &debugUtils;
    }
    check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
    if (validation) {
      debug.pNext = nullptr;
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
      check(create(instance, &debug, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
    }
    std::printf("embed: validation layer %s\n", validation ? "on" : "not installed");

    uint32_t count = 1;
    VkResult listed = vkEnumeratePhysicalDevices(instance, &count, &physical);
    if (listed != VK_INCOMPLETE) check(listed, "vkEnumeratePhysicalDevices");
    if (count == 0) throw std::runtime_error("no Vulkan device");
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical, &properties);
    std::printf("embed: device %s\n", properties.deviceName);

    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, props.data());
    while (family < families && !(props[family].queueFlags & VK_QUEUE_GRAPHICS_BIT)) ++family;

    // What Lava needs, asked of Lava.
    const lava::DeviceRequirements needs = lava::deviceRequirements(properties.apiVersion);
    VkPhysicalDeviceDynamicRenderingFeatures dynamic{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
    dynamic.dynamicRendering = needs.dynamicRendering;
    // Optional, where offered: 64-bit buffer atomics (then told to Lava, below).
    VkPhysicalDeviceShaderAtomicInt64Features atomics{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES};
    VkPhysicalDeviceFeatures2 offered{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    offered.pNext = &atomics;
    vkGetPhysicalDeviceFeatures2(physical, &offered);
    int64Atomics =
        needs.int64Atomics && offered.features.shaderInt64 && atomics.shaderBufferInt64Atomics;
    VkPhysicalDeviceFeatures2 enabled{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    enabled.features.shaderInt64 = int64Atomics;
    atomics.pNext = nullptr;
    atomics.shaderBufferInt64Atomics = int64Atomics;
    enabled.pNext = &dynamic;
    dynamic.pNext = int64Atomics ? &atomics : nullptr;
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = family;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &enabled;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    // Optional extensions, where offered (push descriptors: then told to Lava, below).
    std::vector<const char*> extensions = needs.extensions;
    uint32_t extensionCount = 0;
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &extensionCount, nullptr);
    std::vector<VkExtensionProperties> offeredExtensions(extensionCount);
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &extensionCount,
                                         offeredExtensions.data());
    for (const char* optional : needs.optionalExtensions)
      for (const VkExtensionProperties& e : offeredExtensions)
        if (std::strcmp(e.extensionName, optional) == 0) extensions.push_back(optional);
    pushDescriptors = extensions.size() > needs.extensions.size();
    deviceInfo.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    deviceInfo.ppEnabledExtensionNames = extensions.data();
    check(vkCreateDevice(physical, &deviceInfo, nullptr, &device), "vkCreateDevice");
    vkGetDeviceQueue(device, family, 0, &queue);
  }
  ~Host() {
    vkDestroyDevice(device, nullptr);
    if (messenger) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
      destroy(instance, messenger, nullptr);
    }
    vkDestroyInstance(instance, nullptr);
  }
};

// The host's own attachment: a device-local image and its view.
struct Attachment {
  VkDevice device;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  Attachment(const Host& host, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
             VkImageAspectFlags aspect)
      : device(host.device) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    check(vkCreateImage(device, &info, nullptr, &image), "vkCreateImage");
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(device, image, &requirements);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex =
        memoryType(host.physical, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(device, &alloc, nullptr, &memory), "vkAllocateMemory");
    check(vkBindImageMemory(device, image, memory, 0), "vkBindImageMemory");
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
    check(vkCreateImageView(device, &viewInfo, nullptr, &view), "vkCreateImageView");
  }
  ~Attachment() {
    vkDestroyImageView(device, view, nullptr);
    vkDestroyImage(device, image, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
};

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
             VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
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

// The host's frame images, and the transitions the frame recipe makes between Lava's calls.
struct Frame {
  const Attachment& color;
  const Attachment& depth;  // sampled by the splat: VK_IMAGE_USAGE_SAMPLED_BIT
  VkExtent2D extent;

  // Colour and depth writable. WAR: the last frame's passes, splat and copy read them.
  void toAttachments(VkCommandBuffer cmd) const {
    barrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    barrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            0, kTests,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  }
  // After the backdrop's pass. RAW: the second pass loads the colour; the splat samples the
  // depth (read-only from here), the lines test against it.
  void depthReadOnly(VkCommandBuffer cmd) const {
    barrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    barrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, kTests,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  }
  // `load`: the second pass, over the first's colour, depth read-only; else both cleared.
  void beginRendering(VkCommandBuffer cmd, bool load) const {
    VkRenderingAttachmentInfo colorAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    colorAttachment.imageView = color.view;
    colorAttachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colorAttachment.loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    colorAttachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingAttachmentInfo depthAttachment = colorAttachment;
    depthAttachment.imageView = depth.view;
    depthAttachment.imageLayout = load ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
                                       : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depthAttachment.storeOp = load ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
    depthAttachment.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &colorAttachment;
    rendering.pDepthAttachment = &depthAttachment;
    vkCmdBeginRendering(cmd, &rendering);
  }
  static constexpr VkPipelineStageFlags kTests =
      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
};

int run() {
  const Host host;
  constexpr uint32_t framesInFlight = 2;
  const VkExtent2D extent{256, 256};
  const VkFormat colorFormat = VK_FORMAT_B8G8R8A8_UNORM;  // the host's choice
  const VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
  const Attachment color(host, extent, colorFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                         VK_IMAGE_ASPECT_COLOR_BIT);
  const Attachment depth(host, extent, depthFormat,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                         VK_IMAGE_ASPECT_DEPTH_BIT);
  const Frame target{color, depth, extent};

  // [setup]
  // Lava on the host's handles: it never destroys them. Frame slots: the host's fences.
  lava::DeviceHandles handles{host.instance, host.physical, host.device, host.family, host.queue};
  handles.int64Atomics = host.int64Atomics;  // as the host created the device
  handles.pushDescriptors = host.pushDescriptors;
  handles.framesInFlight = framesInFlight;
  lava::Device device(handles);

  // The lava crater (5,000 slots), as Lava installs it, four times as busy.
  lava::Scene scene = lava::loadScene(std::string(LAVA_SCENES_DIR) + "/crater.toml");
  scene.emitters[0].rate = 4000.0;
  lava::GpuSimulation simulation(device, scene);
  lava::Backdrop backdrop(device, {colorFormat, depthFormat});
  lava::LineRenderer lines(device, {colorFormat, depthFormat});
  lines.setExtent(extent);
  lava::OrbitCamera camera;
  const lava::View view{camera.viewProj(1.0f), extent, camera.eye()};  // what is drawn, where
  // [setup]

  // The host's command buffers, fences and queue: two frames in flight.
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = host.family;
  check(vkCreateCommandPool(host.device, &poolInfo, nullptr, &pool), "vkCreateCommandPool");
  VkCommandBuffer commands[framesInFlight];
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.commandBufferCount = framesInFlight;
  check(vkAllocateCommandBuffers(host.device, &alloc, commands), "vkAllocateCommandBuffers");
  VkFence fences[framesInFlight];
  for (VkFence& fence : fences) {
    VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    check(vkCreateFence(host.device, &info, nullptr, &fence), "vkCreateFence");
  }

  uint64_t steps = 0;
  const int frames = 60;
  for (int frame = 0; frame < frames; ++frame) {
    const uint32_t slot = frame % framesInFlight;  // the index of the fence that guards it
    check(vkWaitForFences(host.device, 1, &fences[slot], VK_TRUE, UINT64_MAX), "vkWaitForFences");
    check(vkResetFences(host.device, 1, &fences[slot]), "vkResetFences");
    const uint32_t stepsThisFrame = 10 + frame % 7;  // as a variable frame time would give
    steps += stepsThisFrame;
    lines.setMode(frame % 2 ? lava::LineMode::Splat : lava::LineMode::Lines);  // both ways
    VkCommandBuffer cmd = commands[slot];
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    // [frame]
    simulation.update(slot, stepsThisFrame);   // CPU: plan the births, stage the schedule
    simulation.recordSimulate(cmd, slot);      // compute: the steps
    target.toAttachments(cmd);                 // host: colour and depth writable
    target.beginRendering(cmd, false);         // clear both
    backdrop.recordDraw(cmd, view, scene);     // ground and solids, writing depth
    vkCmdEndRendering(cmd);
    target.depthReadOnly(cmd);                 // host: DEPTH_STENCIL_READ_ONLY_OPTIMAL
    lines.recordPrepare(cmd, slot, simulation, view, depth.view);  // compute: splat, glow
    target.beginRendering(cmd, true);          // load colour; depth read-only
    lines.recordDraw(cmd, slot, simulation, view);  // lines or the splat's sums, glow
    vkCmdEndRendering(cmd);
    // [frame]
    barrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_TRANSFER_READ_BIT);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(host.queue, 1, &submit, fences[slot]), "vkQueueSubmit");
  }
  check(vkDeviceWaitIdle(host.device), "vkDeviceWaitIdle");

  // The last frame's pixels, read back by the host.
  VkBuffer pixels = VK_NULL_HANDLE;
  VkBufferCreateInfo bufferInfo{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bufferInfo.size = VkDeviceSize{extent.width} * extent.height * 4;
  bufferInfo.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  check(vkCreateBuffer(host.device, &bufferInfo, nullptr, &pixels), "vkCreateBuffer");
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(host.device, pixels, &requirements);
  VkMemoryAllocateInfo memoryInfo{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  memoryInfo.allocationSize = requirements.size;
  memoryInfo.memoryTypeIndex =
      memoryType(host.physical, requirements.memoryTypeBits,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkDeviceMemory pixelMemory = VK_NULL_HANDLE;
  check(vkAllocateMemory(host.device, &memoryInfo, nullptr, &pixelMemory), "vkAllocateMemory");
  check(vkBindBufferMemory(host.device, pixels, pixelMemory, 0), "vkBindBufferMemory");
  VkCommandBuffer cmd = commands[0];
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pixels, 1,
                         &region);
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &toHost, 0, nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  check(vkQueueSubmit(host.queue, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
  check(vkQueueWaitIdle(host.queue), "vkQueueWaitIdle");
  void* mapped = nullptr;
  check(vkMapMemory(host.device, pixelMemory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
  size_t lit = 0;
  const auto* bgra = static_cast<const uint8_t*>(mapped);
  for (size_t i = 0; i < size_t(extent.width) * extent.height; ++i)
    lit += bgra[4 * i + 2] > 150;  // red: lava over the dark backdrop

  // The state, read back by Lava's blocking helper, against the CPU reference.
  const lava::State gpu = simulation.state();
  lava::CpuSimulation reference(scene);
  reference.advance(steps);
  const lava::Comparison c = lava::compare(gpu.particles, reference.state().particles);
  std::printf(
      "embed: %d frames, %llu steps, %llu/%llu slots bit-identical to the CPU reference, "
      "%zu lit pixels, %zu validation messages\n",
      frames, static_cast<unsigned long long>(steps), static_cast<unsigned long long>(c.equal),
      static_cast<unsigned long long>(c.particles), lit, messages.size());
  for (const std::string& m : messages) std::fprintf(stderr, "embed: validation: %s\n", m.c_str());

  vkUnmapMemory(host.device, pixelMemory);
  vkDestroyBuffer(host.device, pixels, nullptr);
  vkFreeMemory(host.device, pixelMemory, nullptr);
  for (VkFence fence : fences) vkDestroyFence(host.device, fence, nullptr);
  vkDestroyCommandPool(host.device, pool, nullptr);
  const bool pass = c.equal == c.particles && lit > 1000 && messages.empty();
  std::printf("embed: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}

}  // namespace

int main() {
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 1;
  }
}
