// A host of render passes, as Dear ImGui's Vulkan example and many engines are: a GLFW
// window, a swapchain, two VkRenderPasses a frame. Lava's pipelines are built for the
// host's passes (RenderFormats::renderPass), and its frame recipe (docs/library.md) runs
// between them: the backdrop in the first pass writes depth; the pass leaves it read-only;
// Lava's splat tests against it outside the passes; the lines and glow draw in the second.
// The device is created without dynamic rendering: nothing here needs it.
//
//   lava_renderpass [frames [scene]]   (frames 0 or none: until the window closes; scene a
//                                      preset's name, volcano.toml by default: eruption.toml
//                                      draws the flow's molten surface in the same passes)
//
// Exits 0 when the state equals Lava's CPU reference bit for bit and the validation layer
// (with synchronization validation, when installed) said nothing. The host's own Vulkan is
// examples/common/vulkan_host.h.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <lava/lava.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "vulkan_host.h"  // the host's instance, device, images, frames (examples/common)

namespace {

using vkhost::check;

constexpr VkFormat kColor = VK_FORMAT_B8G8R8A8_UNORM, kDepth = VK_FORMAT_D32_SFLOAT;
constexpr VkImageLayout kDepthWrite = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
constexpr VkImageLayout kDepthRead = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
constexpr VkPipelineStageFlags kTests =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
constexpr VkPipelineStageFlags kColorStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;

// The passes' dependencies, which carry the frame from pass to pass (`second`: the lines'
// pass; else the backdrop's).
void dependencies(bool second, VkSubpassDependency (&deps)[2]) {
  // In: the first pass waits for the acquired image (its semaphore's stage) and for the
  // last frame's depth tests and splat to finish with the depth (WAR); the second, for
  // the first pass's colour.
  deps[0] = {VK_SUBPASS_EXTERNAL,
             0,
             kColorStage | kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             kColorStage | kTests,
             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             0};
  // Out: the first pass's colour to the second's load, its depth to the splat (compute)
  // and the second's tests; the second's colour to presentation.
  deps[1] = {0,
             VK_SUBPASS_EXTERNAL,
             kColorStage | kTests,
             second ? VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT
                    : kColorStage | kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             second ? VkAccessFlags{0}
                    : VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_SHADER_READ_BIT,
             0};
}

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
  a[0].initialLayout =
      second ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
  a[0].finalLayout =
      second ? VK_IMAGE_LAYOUT_PRESENT_SRC_KHR : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
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
  VkSubpassDependency deps[2];
  dependencies(second, deps);
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

// The swapchain, its views, one depth image (sampled by Lava's splat) and a framebuffer
// per image and pass; rebuilt when the window changes size.
struct Swapchain {
  const vkhost::Device& vk;
  VkSurfaceKHR surface;
  VkRenderPass passes[2];
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  VkExtent2D extent{0, 0};
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers[2];
  std::vector<VkSemaphore> rendered;  // per image: the frame's end, waited by presentation
  std::unique_ptr<vkhost::Image> depth;

  VkDevice device() const { return vk.handles.device; }
  void create(GLFWwindow* window) {
    VkSurfaceCapabilitiesKHR caps;
    check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(vk.handles.physicalDevice, surface, &caps),
          "capabilities");
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
    check(vkCreateSwapchainKHR(device(), &info, nullptr, &handle), "vkCreateSwapchainKHR");
    depth = std::make_unique<vkhost::Image>(
        vk.handles, extent, kDepth,
        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
        VK_IMAGE_ASPECT_DEPTH_BIT);
    uint32_t count = 0;
    vkGetSwapchainImagesKHR(device(), handle, &count, nullptr);
    std::vector<VkImage> images(count);
    vkGetSwapchainImagesKHR(device(), handle, &count, images.data());
    for (VkImage image : images) addImage(image);
  }
  // A swapchain image's view, its framebuffer for each pass, its semaphore.
  void addImage(VkImage image) {
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = kColor;
    viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    views.emplace_back();
    check(vkCreateImageView(device(), &viewInfo, nullptr, &views.back()), "vkCreateImageView");
    const VkImageView attachments[2] = {views.back(), depth->view};
    for (int p = 0; p < 2; ++p) {
      VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
      fb.renderPass = passes[p];
      fb.attachmentCount = 2;
      fb.pAttachments = attachments;
      fb.width = extent.width;
      fb.height = extent.height;
      fb.layers = 1;
      framebuffers[p].emplace_back();
      check(vkCreateFramebuffer(device(), &fb, nullptr, &framebuffers[p].back()), "framebuffer");
    }
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    rendered.emplace_back();
    check(vkCreateSemaphore(device(), &semaphore, nullptr, &rendered.back()), "semaphore");
  }
  void destroy() {
    for (int p = 0; p < 2; ++p) {
      for (VkFramebuffer fb : framebuffers[p]) vkDestroyFramebuffer(device(), fb, nullptr);
      framebuffers[p].clear();
    }
    for (VkImageView v : views) vkDestroyImageView(device(), v, nullptr);
    for (VkSemaphore s : rendered) vkDestroySemaphore(device(), s, nullptr);
    views.clear();
    rendered.clear();
    depth.reset();
    vkDestroySwapchainKHR(device(), handle, nullptr);
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

// Lava's objects on the host's handles, its pipelines built for the host's passes.
struct Lava {
  lava::Device device;
  lava::Scene scene;
  lava::GpuSimulation simulation;
  lava::Backdrop backdrop;
  lava::LineRenderer lines;
  uint64_t steps = 0;

  Lava(const lava::DeviceHandles& handles, const Swapchain& swapchain, const std::string& preset)
      : device(handles),
        scene(lava::loadScene(std::string(LAVA_SCENES_DIR) + "/" + preset)),
        simulation(device, scene),
        backdrop(device, {kColor, kDepth, swapchain.passes[0], 0}),
        lines(device, {kColor, kDepth, swapchain.passes[1], 0}) {
    lines.setMode(lava::LineMode::Splat);  // tested against the backdrop's depth
    lines.setExtent(swapchain.extent);
  }
  // One frame of the recipe between the host's two passes: 16 ms of lava.
  void record(VkCommandBuffer cmd, uint32_t slot, const Swapchain& swapchain, uint32_t image,
              const lava::View& view) {
    simulation.update(slot, 16);
    steps += 16;
    simulation.recordSimulate(cmd, slot);
    beginPass(cmd, swapchain, 0, image);
    backdrop.recordDraw(cmd, view, scene);
    vkCmdEndRenderPass(cmd);  // the depth is read-only now (the pass's final layout)
    lines.recordPrepare(cmd, slot, simulation, view, swapchain.depth->view);
    beginPass(cmd, swapchain, 1, image);
    lines.recordDraw(cmd, slot, simulation, view);
    vkCmdEndRenderPass(cmd);
  }
};

// Rebuilds the swapchain at the window's size, once it has an area, and tells Lava.
void rebuild(Swapchain& swapchain, Lava& lava, GLFWwindow* window) {
  for (int w = 0, h = 0; glfwGetFramebufferSize(window, &w, &h), w == 0 || h == 0;)
    glfwWaitEvents();
  vkDeviceWaitIdle(swapchain.device());
  swapchain.destroy();
  swapchain.create(window);
  lava.lines.setExtent(swapchain.extent);
}

// `frames` frames (0: until the window closes), resized as the window is; then the state
// against the CPU reference. 0 when they are equal bit for bit.
int drawFrames(const vkhost::Device& vk, Swapchain& swapchain, GLFWwindow* window, int frames,
               const std::string& preset) {
  constexpr uint32_t kFramesInFlight = 2;  // the host's: a command buffer, fence, semaphore each
  lava::DeviceHandles handles = vk.handles;
  handles.framesInFlight = kFramesInFlight;
  Lava lava(handles, swapchain, preset);
  vkhost::Frames slots(vk.handles, kFramesInFlight);
  VkSemaphore acquired[kFramesInFlight];
  for (VkSemaphore& semaphore : acquired) {
    VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    check(vkCreateSemaphore(vk.handles.device, &info, nullptr, &semaphore), "semaphore");
  }
  lava::OrbitCamera camera;
  bool stale = false;  // the window changed size: rebuild before the next frame
  for (int frame = 0; (frames == 0 || frame < frames) && !glfwWindowShouldClose(window); ++frame) {
    glfwPollEvents();
    int width = 0, height = 0;  // not every driver reports a resize as out of date
    glfwGetFramebufferSize(window, &width, &height);
    if (stale || uint32_t(width) != swapchain.extent.width ||
        uint32_t(height) != swapchain.extent.height)
      rebuild(swapchain, lava, window);
    const uint32_t slot = uint32_t(frame) % kFramesInFlight;  // the fence's index
    slots.wait(slot);
    uint32_t image = 0;
    const VkResult got = vkAcquireNextImageKHR(vk.handles.device, swapchain.handle, UINT64_MAX,
                                               acquired[slot], VK_NULL_HANDLE, &image);
    stale = got == VK_ERROR_OUT_OF_DATE_KHR;
    if (stale) continue;
    if (got != VK_SUBOPTIMAL_KHR) check(got, "vkAcquireNextImageKHR");
    const float aspect = float(swapchain.extent.width) / float(swapchain.extent.height);
    const lava::View view{camera.viewProj(aspect), swapchain.extent, camera.eye()};
    lava.record(slots.begin(slot), slot, swapchain, image, view);
    slots.submit(slot, acquired[slot], VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                 swapchain.rendered[image]);
    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &swapchain.rendered[image];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain.handle;
    present.pImageIndices = &image;
    const VkResult shown = vkQueuePresentKHR(vk.handles.queue, &present);
    stale = shown == VK_ERROR_OUT_OF_DATE_KHR || shown == VK_SUBOPTIMAL_KHR;
    if (!stale) check(shown, "vkQueuePresentKHR");
  }
  check(vkDeviceWaitIdle(vk.handles.device), "vkDeviceWaitIdle");
  for (VkSemaphore semaphore : acquired) vkDestroySemaphore(vk.handles.device, semaphore, nullptr);

  lava::CpuSimulation reference(lava.scene);
  reference.advance(lava.steps);
  const std::vector<lava::Particle> gpu = lava.simulation.state().particles;
  const uint64_t equal = vkhost::identicalSlots(gpu, reference.state().particles);
  std::printf(
      "renderpass: %llu steps at %ux%u, %llu/%zu slots bit-identical to the CPU "
      "reference, %zu validation messages\n",
      static_cast<unsigned long long>(lava.steps), swapchain.extent.width, swapchain.extent.height,
      static_cast<unsigned long long>(equal), gpu.size(), vk.messages().size());
  return equal == gpu.size() ? 0 : 1;
}

// The host's Vulkan, made from what GLFW and Lava ask for: GLFW's instance extensions, the
// swapchain, a queue that presents, and no dynamic rendering (Lava draws in the passes).
vkhost::DeviceOptions windowDevice() {
  vkhost::DeviceOptions options;
  options.name = "renderpass";
  uint32_t count = 0;
  const char** extensions = glfwGetRequiredInstanceExtensions(&count);
  options.instanceExtensions.assign(extensions, extensions + count);
  options.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  options.dynamicRendering = false;
  options.presents = [](VkInstance instance, VkPhysicalDevice physical, uint32_t family) {
    return glfwGetPhysicalDevicePresentationSupport(instance, physical, family) == GLFW_TRUE;
  };
  return options;
}

int run(int frames, const std::string& preset) {
  if (!glfwInit()) throw std::runtime_error("no display for GLFW");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* window = glfwCreateWindow(640, 360, "Lava in render passes", nullptr, nullptr);
  if (!window) throw std::runtime_error("GLFW could not open a window");
  int status = 1;
  {
    const vkhost::Device vk(windowDevice());
    std::printf("renderpass: validation layer %s\n", vk.validation ? "on" : "not installed");
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    check(glfwCreateWindowSurface(vk.handles.instance, window, nullptr, &surface), "surface");
    Swapchain swapchain{
        vk,
        surface,
        {createRenderPass(vk.handles.device, false), createRenderPass(vk.handles.device, true)}};
    swapchain.create(window);
    // Lava's objects gone before the host's.
    status = drawFrames(vk, swapchain, window, frames, preset);
    swapchain.destroy();
    for (VkRenderPass pass : swapchain.passes)
      vkDestroyRenderPass(vk.handles.device, pass, nullptr);
    vkDestroySurfaceKHR(vk.handles.instance, surface, nullptr);
    for (const std::string& m : vk.messages())
      std::fprintf(stderr, "renderpass: validation: %s\n", m.c_str());
    if (!vk.messages().empty()) status = 1;
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  std::printf("renderpass: %s\n", status == 0 ? "PASS" : "FAIL");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc > 1 ? std::atoi(argv[1]) : 0, argc > 2 ? argv[2] : "volcano.toml");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderpass: %s\n", e.what());
    return 1;
  }
}
