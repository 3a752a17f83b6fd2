// A host of render passes, as Dear ImGui's Vulkan example and many engines are: a GLFW
// window, a swapchain, two VkRenderPasses a frame. Lava's pipelines are built for the
// host's passes (RenderFormats::renderPass), and its frame recipe (docs/library.md) runs
// between them: the backdrop in the first pass writes depth; the pass leaves it read-only;
// Lava's splat tests against it outside the passes; the lines and glow draw in the second.
// The device is created without dynamic rendering: nothing here needs it.
//
//   lava_renderpass [frames]   (0 or none: until the window closes)
//
// Exits 0 when the state equals Lava's CPU reference bit for bit and the validation layer
// (with synchronization validation, when installed) said nothing.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <lava/lava.h>
#include <lava/validation.h>  // lava::compare

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS && result != VK_SUBOPTIMAL_KHR)
    throw std::runtime_error(std::string(what) + " failed: " + lava::resultName(result));
}

std::vector<std::string> messages;  // the validation layer's, counted at exit
VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                         VkDebugUtilsMessageTypeFlagsEXT type,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  if (type & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT) messages.emplace_back(data->pMessage);
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

// The host's Vulkan: instance (with the validation layer when installed), device, queue,
// made from what GLFW and Lava ask for.
struct Context {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkQueue queue = VK_NULL_HANDLE;

  Context() {
    const bool validation = hasLayer("VK_LAYER_KHRONOS_validation");
    uint32_t glfwCount = 0;
    const char** glfwExtensions = glfwGetRequiredInstanceExtensions(&glfwCount);
    std::vector<const char*> extensions(glfwExtensions, glfwExtensions + glfwCount);
    if (validation) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    const char* layer = "VK_LAYER_KHRONOS_validation";
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    VkDebugUtilsMessengerCreateInfoEXT debug{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    debug.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    debug.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    debug.pfnUserCallback = &onMessage;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (validation) {
      debug.pNext = &features;
      info.pNext = &debug;
      info.enabledLayerCount = 1;
      info.ppEnabledLayerNames = &layer;
    }
    check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
    if (validation) {
      debug.pNext = nullptr;
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
      check(create(instance, &debug, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
    }
    std::printf("renderpass: validation layer %s\n", validation ? "on" : "not installed");
    uint32_t count = 1;
    const VkResult listed = vkEnumeratePhysicalDevices(instance, &count, &physical);
    if (listed != VK_INCOMPLETE) check(listed, "vkEnumeratePhysicalDevices");
    if (count == 0) throw std::runtime_error("no Vulkan device");
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, props.data());
    while (family < families && (!(props[family].queueFlags & VK_QUEUE_GRAPHICS_BIT) ||
                                 !glfwGetPhysicalDevicePresentationSupport(instance, physical,
                                                                           family)))
      ++family;
    if (family == families) throw std::runtime_error("no queue that draws and presents");
    // Lava's required extensions (none on 1.3) and the swapchain; no dynamic rendering.
    std::vector<const char*> deviceExtensions = lava::deviceRequirements(instance, physical).extensions;
    deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = family;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = uint32_t(deviceExtensions.size());
    deviceInfo.ppEnabledExtensionNames = deviceExtensions.data();
    check(vkCreateDevice(physical, &deviceInfo, nullptr, &device), "vkCreateDevice");
    vkGetDeviceQueue(device, family, 0, &queue);
  }
  ~Context() {
    vkDestroyDevice(device, nullptr);
    if (messenger)
      reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"))(instance, messenger,
                                                                              nullptr);
    vkDestroyInstance(instance, nullptr);
  }
};

constexpr VkFormat kColor = VK_FORMAT_B8G8R8A8_UNORM, kDepth = VK_FORMAT_D32_SFLOAT;
constexpr VkImageLayout kDepthWrite = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
constexpr VkImageLayout kDepthRead = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
constexpr VkPipelineStageFlags kTests =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
constexpr VkPipelineStageFlags kColorStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;

// `second`: the lines' pass (loads the colour, depth read-only, then presents); else the
// backdrop's (clears both; leaves the depth read-only for Lava's splat). The dependencies
// carry the frame from pass to pass; Lava's own barriers are recorded outside them.
VkRenderPass createRenderPass(VkDevice device, bool second) {
  VkAttachmentDescription a[2]{};
  for (VkAttachmentDescription& d : a) {
    d.samples = VK_SAMPLE_COUNT_1_BIT;
    d.loadOp = second ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    d.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    d.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    d.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  }
  a[0].format = kColor;
  a[0].initialLayout = second ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
  a[0].finalLayout = second ? VK_IMAGE_LAYOUT_PRESENT_SRC_KHR : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a[1].format = kDepth;
  a[1].storeOp = second ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
  a[1].initialLayout = second ? kDepthRead : VK_IMAGE_LAYOUT_UNDEFINED;
  a[1].finalLayout = kDepthRead;
  const VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkAttachmentReference depth{1, second ? kDepthRead : kDepthWrite};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color;
  subpass.pDepthStencilAttachment = &depth;
  VkSubpassDependency deps[2]{};
  // In: the first pass waits for the acquired image (its semaphore's stage) and for the
  // last frame's depth tests and splat to finish with the depth (WAR); the second, for
  // the first pass's colour.
  deps[0] = {VK_SUBPASS_EXTERNAL, 0, kColorStage | kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             kColorStage | kTests,
             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             0};
  // Out: the first pass's colour to the second's load, its depth to the splat (compute)
  // and the second's tests; the second's colour to presentation.
  deps[1] = {0, VK_SUBPASS_EXTERNAL, kColorStage | kTests,
             second ? VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT
                    : kColorStage | kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             second ? VkAccessFlags{0}
                    : VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_SHADER_READ_BIT,
             0};
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 2;
  info.pAttachments = a;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 2;
  info.pDependencies = deps;
  VkRenderPass pass = VK_NULL_HANDLE;
  check(vkCreateRenderPass(device, &info, nullptr, &pass), "vkCreateRenderPass");
  return pass;
}

uint32_t memoryType(VkPhysicalDevice physical, uint32_t bits) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory);
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
    if ((bits & (1u << i)) &&
        (memory.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
      return i;
  throw std::runtime_error("no device-local memory");
}

// The swapchain, its views, one depth image (sampled by Lava's splat) and a framebuffer
// per image and pass; rebuilt when the window changes size.
struct Swapchain {
  const Context& vk;
  VkSurfaceKHR surface;
  VkRenderPass passes[2];
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  VkExtent2D extent{0, 0};
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers[2];
  std::vector<VkSemaphore> rendered;  // per image: the frame's end, waited by presentation
  VkImage depth = VK_NULL_HANDLE;
  VkDeviceMemory depthMemory = VK_NULL_HANDLE;
  VkImageView depthView = VK_NULL_HANDLE;

  void create(GLFWwindow* window) {
    VkSurfaceCapabilitiesKHR caps;
    check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(vk.physical, surface, &caps), "capabilities");
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    extent = caps.currentExtent.width != UINT32_MAX ? caps.currentExtent
                                                    : VkExtent2D{uint32_t(w), uint32_t(h)};
    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface;
    info.minImageCount = caps.minImageCount + 1;
    if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = kColor;
    info.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    info.clipped = VK_TRUE;
    check(vkCreateSwapchainKHR(vk.device, &info, nullptr, &handle), "vkCreateSwapchainKHR");
    uint32_t count = 0;
    vkGetSwapchainImagesKHR(vk.device, handle, &count, nullptr);
    std::vector<VkImage> images(count);
    vkGetSwapchainImagesKHR(vk.device, handle, &count, images.data());

    VkImageCreateInfo depthInfo{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    depthInfo.imageType = VK_IMAGE_TYPE_2D;
    depthInfo.format = kDepth;
    depthInfo.extent = {extent.width, extent.height, 1};
    depthInfo.mipLevels = depthInfo.arrayLayers = 1;
    depthInfo.samples = VK_SAMPLE_COUNT_1_BIT;
    depthInfo.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    check(vkCreateImage(vk.device, &depthInfo, nullptr, &depth), "vkCreateImage");
    VkMemoryRequirements needs;
    vkGetImageMemoryRequirements(vk.device, depth, &needs);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = needs.size;
    alloc.memoryTypeIndex = memoryType(vk.physical, needs.memoryTypeBits);
    check(vkAllocateMemory(vk.device, &alloc, nullptr, &depthMemory), "vkAllocateMemory");
    check(vkBindImageMemory(vk.device, depth, depthMemory, 0), "vkBindImageMemory");
    depthView = view(depth, kDepth, VK_IMAGE_ASPECT_DEPTH_BIT);

    for (VkImage image : images) {
      views.push_back(view(image, kColor, VK_IMAGE_ASPECT_COLOR_BIT));
      const VkImageView attachments[2] = {views.back(), depthView};
      for (int p = 0; p < 2; ++p) {
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = passes[p];
        fb.attachmentCount = 2;
        fb.pAttachments = attachments;
        fb.width = extent.width;
        fb.height = extent.height;
        fb.layers = 1;
        framebuffers[p].emplace_back();
        check(vkCreateFramebuffer(vk.device, &fb, nullptr, &framebuffers[p].back()), "framebuffer");
      }
      VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
      rendered.emplace_back();
      check(vkCreateSemaphore(vk.device, &semaphore, nullptr, &rendered.back()), "semaphore");
    }
  }
  VkImageView view(VkImage image, VkFormat format, VkImageAspectFlags aspect) const {
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.image = image;
    info.viewType = VK_IMAGE_VIEW_TYPE_2D;
    info.format = format;
    info.subresourceRange = {aspect, 0, 1, 0, 1};
    VkImageView v = VK_NULL_HANDLE;
    check(vkCreateImageView(vk.device, &info, nullptr, &v), "vkCreateImageView");
    return v;
  }
  void destroy() {
    for (int p = 0; p < 2; ++p) {
      for (VkFramebuffer fb : framebuffers[p]) vkDestroyFramebuffer(vk.device, fb, nullptr);
      framebuffers[p].clear();
    }
    for (VkImageView v : views) vkDestroyImageView(vk.device, v, nullptr);
    for (VkSemaphore s : rendered) vkDestroySemaphore(vk.device, s, nullptr);
    views.clear();
    rendered.clear();
    vkDestroyImageView(vk.device, depthView, nullptr);
    vkDestroyImage(vk.device, depth, nullptr);
    vkFreeMemory(vk.device, depthMemory, nullptr);
    vkDestroySwapchainKHR(vk.device, handle, nullptr);
  }
};

void beginPass(VkCommandBuffer cmd, const Swapchain& swapchain, int pass, uint32_t image) {
  VkClearValue clear[2]{};
  clear[0].color = {{0.012f, 0.010f, 0.018f, 1.0f}};
  clear[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  info.renderPass = swapchain.passes[pass];
  info.framebuffer = swapchain.framebuffers[pass][image];
  info.renderArea = {{0, 0}, swapchain.extent};
  info.clearValueCount = 2;
  info.pClearValues = clear;
  vkCmdBeginRenderPass(cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
}

int run(int frames) {
  if (!glfwInit()) throw std::runtime_error("no display for GLFW");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* window = glfwCreateWindow(640, 360, "Lava in render passes", nullptr, nullptr);
  if (!window) throw std::runtime_error("GLFW could not open a window");
  int status = 1;
  {
    const Context vk;
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    check(glfwCreateWindowSurface(vk.instance, window, nullptr, &surface), "surface");
    Swapchain swapchain{vk, surface, {createRenderPass(vk.device, false),
                                      createRenderPass(vk.device, true)}};
    swapchain.create(window);

    // Lava on the host's handles, its pipelines for the host's passes.
    constexpr uint32_t kFramesInFlight = 2;
    lava::DeviceHandles handles{vk.instance, vk.physical, vk.device, vk.family, vk.queue};
    handles.dynamicRendering = false;  // created without it: Lava draws in the passes
    handles.framesInFlight = kFramesInFlight;
    {
      lava::Device device(handles);
      const lava::Scene scene = lava::loadScene(std::string(LAVA_SCENES_DIR) + "/volcano.toml");
      lava::GpuSimulation simulation(device, scene);
      const lava::Backdrop backdrop(device, {kColor, kDepth, swapchain.passes[0], 0});
      lava::LineRenderer lines(device, {kColor, kDepth, swapchain.passes[1], 0});
      lines.setMode(lava::LineMode::Splat);  // tested against the backdrop's depth
      lines.setExtent(swapchain.extent);

      // The host's frames in flight: a command buffer, a fence, an acquire semaphore each.
      VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
      poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
      poolInfo.queueFamilyIndex = vk.family;
      VkCommandPool pool = VK_NULL_HANDLE;
      check(vkCreateCommandPool(vk.device, &poolInfo, nullptr, &pool), "vkCreateCommandPool");
      VkCommandBuffer commands[kFramesInFlight];
      VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
      alloc.commandPool = pool;
      alloc.commandBufferCount = kFramesInFlight;
      check(vkAllocateCommandBuffers(vk.device, &alloc, commands), "vkAllocateCommandBuffers");
      VkFence fences[kFramesInFlight];
      VkSemaphore acquired[kFramesInFlight];
      for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        check(vkCreateFence(vk.device, &fence, nullptr, &fences[i]), "vkCreateFence");
        VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        check(vkCreateSemaphore(vk.device, &semaphore, nullptr, &acquired[i]), "semaphore");
      }

      lava::OrbitCamera camera;
      uint64_t steps = 0;
      bool stale = false;  // the window changed size: rebuild before the next frame
      for (int frame = 0; (frames == 0 || frame < frames) && !glfwWindowShouldClose(window);
           ++frame) {
        glfwPollEvents();
        int width = 0, height = 0;  // not every driver reports a resize as out of date
        glfwGetFramebufferSize(window, &width, &height);
        stale = stale || uint32_t(width) != swapchain.extent.width ||
                uint32_t(height) != swapchain.extent.height;
        if (stale) {  // rebuilt once the window has an area, and Lava told the size
          for (int w = 0, h = 0; glfwGetFramebufferSize(window, &w, &h), w == 0 || h == 0;)
            glfwWaitEvents();
          vkDeviceWaitIdle(vk.device);
          swapchain.destroy();
          swapchain.create(window);
          lines.setExtent(swapchain.extent);
          stale = false;
        }
        const uint32_t slot = uint32_t(frame) % kFramesInFlight;  // the fence's index
        check(vkWaitForFences(vk.device, 1, &fences[slot], VK_TRUE, UINT64_MAX), "wait");
        uint32_t image = 0;
        const VkResult got = vkAcquireNextImageKHR(vk.device, swapchain.handle, UINT64_MAX,
                                                   acquired[slot], VK_NULL_HANDLE, &image);
        if (got == VK_ERROR_OUT_OF_DATE_KHR) {
          stale = true;
          continue;
        }
        check(got, "vkAcquireNextImageKHR");
        check(vkResetFences(vk.device, 1, &fences[slot]), "vkResetFences");
        const lava::View view{
            camera.viewProj(float(swapchain.extent.width) / float(swapchain.extent.height)),
            swapchain.extent, camera.eye()};
        VkCommandBuffer cmd = commands[slot];
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
        simulation.update(slot, 16);  // 16 ms of lava a frame
        steps += 16;
        simulation.recordSimulate(cmd, slot);
        beginPass(cmd, swapchain, 0, image);
        backdrop.recordDraw(cmd, view, scene);
        vkCmdEndRenderPass(cmd);  // the depth is read-only now (the pass's final layout)
        lines.recordPrepare(cmd, slot, simulation, view, swapchain.depthView);
        beginPass(cmd, swapchain, 1, image);
        lines.recordDraw(cmd, slot, simulation, view);
        vkCmdEndRenderPass(cmd);
        check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

        const VkPipelineStageFlags waitStage = kColorStage;
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.waitSemaphoreCount = 1;
        submit.pWaitSemaphores = &acquired[slot];
        submit.pWaitDstStageMask = &waitStage;
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        submit.signalSemaphoreCount = 1;
        submit.pSignalSemaphores = &swapchain.rendered[image];
        check(vkQueueSubmit(vk.queue, 1, &submit, fences[slot]), "vkQueueSubmit");
        VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
        present.waitSemaphoreCount = 1;
        present.pWaitSemaphores = &swapchain.rendered[image];
        present.swapchainCount = 1;
        present.pSwapchains = &swapchain.handle;
        present.pImageIndices = &image;
        const VkResult shown = vkQueuePresentKHR(vk.queue, &present);
        stale = shown == VK_ERROR_OUT_OF_DATE_KHR || shown == VK_SUBOPTIMAL_KHR;
        if (!stale) check(shown, "vkQueuePresentKHR");
      }
      check(vkDeviceWaitIdle(vk.device), "vkDeviceWaitIdle");

      lava::CpuSimulation reference(scene);
      reference.advance(steps);
      const lava::Comparison c =
          lava::compare(simulation.state().particles, reference.state().particles);
      std::printf("renderpass: %llu steps at %ux%u, %llu/%llu slots bit-identical to the CPU "
                  "reference, %zu validation messages\n",
                  static_cast<unsigned long long>(steps), swapchain.extent.width,
                  swapchain.extent.height, static_cast<unsigned long long>(c.equal),
                  static_cast<unsigned long long>(c.particles), messages.size());
      status = c.equal == c.particles ? 0 : 1;
      for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        vkDestroyFence(vk.device, fences[i], nullptr);
        vkDestroySemaphore(vk.device, acquired[i], nullptr);
      }
      vkDestroyCommandPool(vk.device, pool, nullptr);
    }  // Lava's objects, then its Device, before the host's
    swapchain.destroy();
    for (VkRenderPass pass : swapchain.passes) vkDestroyRenderPass(vk.device, pass, nullptr);
    vkDestroySurfaceKHR(vk.instance, surface, nullptr);
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  for (const std::string& m : messages) std::fprintf(stderr, "renderpass: validation: %s\n", m.c_str());
  if (!messages.empty()) status = 1;
  std::printf("renderpass: %s\n", status == 0 ? "PASS" : "FAIL");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc > 1 ? std::atoi(argv[1]) : 0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderpass: %s\n", e.what());
    return 1;
  }
}
