// Lava as a host embeds it (docs/library.md): the host's own instance and device, borrowed and
// never destroyed; the simulation recorded into the host's command buffers with frames in flight
// and a step count that changes every frame, bit-identical to the CPU reference; lines drawn into a
// host image of a format Lava was not written for.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "lava/lava.h"
#include "vulkan_test.h"

namespace lava {
namespace {

// A host's instance and device, made without Lava, with the validation layer and a
// messenger of the host's own.
class HostDevice {
 public:
  HostDevice() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT debug{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    debug.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    debug.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    debug.pfnUserCallback = [](VkDebugUtilsMessageSeverityFlagBitsEXT,
                               VkDebugUtilsMessageTypeFlagsEXT,
                               const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
      static_cast<HostDevice*>(self)->messages.emplace_back(data->pMessage);
      return VK_FALSE;
    };
    debug.pUserData = this;
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    debug.pNext = &features;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = &debug;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &layer;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = &extension;
    EXPECT_EQ(vkCreateInstance(&info, nullptr, &handles.instance), VK_SUCCESS);
    debug.pNext = nullptr;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(handles.instance, "vkCreateDebugUtilsMessengerEXT"));
    EXPECT_EQ(create(handles.instance, &debug, nullptr, &messenger_), VK_SUCCESS);
    uint32_t count = 1;
    vkEnumeratePhysicalDevices(handles.instance, &count, &handles.physicalDevice);
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(handles.physicalDevice, &properties);
    const DeviceRequirements needs = deviceRequirements(properties.apiVersion);
    VkPhysicalDeviceDynamicRenderingFeatures dynamic{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
    dynamic.dynamicRendering = VK_TRUE;
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &dynamic;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queue;
    deviceInfo.enabledExtensionCount = static_cast<uint32_t>(needs.extensions.size());
    deviceInfo.ppEnabledExtensionNames = needs.extensions.data();
    EXPECT_EQ(vkCreateDevice(handles.physicalDevice, &deviceInfo, nullptr, &handles.device),
              VK_SUCCESS);
    vkGetDeviceQueue(handles.device, 0, 0, &handles.queue);
  }
  ~HostDevice() {
    vkDestroyDevice(handles.device, nullptr);
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(handles.instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(handles.instance, messenger_, nullptr);
    vkDestroyInstance(handles.instance, nullptr);
  }
  HostDevice(const HostDevice&) = delete;
  HostDevice& operator=(const HostDevice&) = delete;

  DeviceHandles handles;
  std::vector<std::string> messages;

 private:
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
};

// The host's frames: a command buffer and a fence per frame in flight.
class HostFrames {
 public:
  HostFrames(VkDevice device, uint32_t frames)
      : device_(device), commands_(frames), fences_(frames) {
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    EXPECT_EQ(vkCreateCommandPool(device, &pool, nullptr, &pool_), VK_SUCCESS);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.commandBufferCount = frames;
    EXPECT_EQ(vkAllocateCommandBuffers(device, &alloc, commands_.data()), VK_SUCCESS);
    for (VkFence& fence : fences_) {
      VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      EXPECT_EQ(vkCreateFence(device, &info, nullptr, &fence), VK_SUCCESS);
    }
  }
  ~HostFrames() {
    vkDeviceWaitIdle(device_);
    for (VkFence fence : fences_) vkDestroyFence(device_, fence, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
  }
  // Waits until `slot`'s previous frame finished, then begins its command buffer.
  VkCommandBuffer begin(uint32_t slot) {
    EXPECT_EQ(vkWaitForFences(device_, 1, &fences_[slot], VK_TRUE, UINT64_MAX), VK_SUCCESS);
    EXPECT_EQ(vkResetFences(device_, 1, &fences_[slot]), VK_SUCCESS);
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    EXPECT_EQ(vkBeginCommandBuffer(commands_[slot], &info), VK_SUCCESS);
    return commands_[slot];
  }
  void submit(VkQueue queue, uint32_t slot) {
    EXPECT_EQ(vkEndCommandBuffer(commands_[slot]), VK_SUCCESS);
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commands_[slot];
    EXPECT_EQ(vkQueueSubmit(queue, 1, &submit, fences_[slot]), VK_SUCCESS);
  }

 private:
  VkDevice device_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::vector<VkCommandBuffer> commands_;
  std::vector<VkFence> fences_;
};

class Embedding : public ::testing::TestWithParam<uint32_t> {};

TEST_P(Embedding, FramesInFlightWithChangingStepCountsMatchTheCpu) {
  HostDevice host;
  {
    Device device(host.handles);
    EXPECT_FALSE(device.ownsHandles());
    Scene scene;
    scene.emitters[0].particles = 3000;
    scene.emitters[0].rate = 25000.0;  // wraps the ring several times per second
    GpuSimulationOptions options;
    options.framesInFlight = 3;
    options.maxStepsPerFrame = 64;
    options.stepsPerDispatch = GetParam();
    GpuSimulation gpu(device, scene, options);
    CpuSimulation cpu(scene);
    HostFrames frames(host.handles.device, options.framesInFlight);
    uint64_t steps = 0;
    for (uint32_t frame = 0; frame < 60; ++frame) {
      const uint32_t slot = frame % options.framesInFlight;
      const uint32_t count = (frame * 7) % 23;  // 0 some frames, up to 22
      VkCommandBuffer commands = frames.begin(slot);
      gpu.update(slot, count);
      if (count > 0) {  // planning over steps not recorded yet would lose them
        EXPECT_THROW(gpu.update(slot, count), InvalidArgument);
        EXPECT_EQ(gpu.step(), steps + count);
      }
      gpu.recordSimulate(commands, slot);
      gpu.recordSimulate(commands, slot);  // a second record of the same plan records nothing
      frames.submit(host.handles.queue, slot);
      steps += count;
    }
    vkDeviceWaitIdle(host.handles.device);
    EXPECT_EQ(gpu.step(), steps);
    cpu.advance(steps);
    const State g = gpu.state(), c = cpu.state();
    EXPECT_EQ(g.step, c.step);
    EXPECT_EQ(g.clocks[0].serial, c.clocks[0].serial);
    const Comparison diff = compare(g.particles, c.particles);
    EXPECT_EQ(diff.equal, diff.particles) << "max ULP " << diff.maxUlp;
  }
  // Lava destroyed nothing of the host's: its device still works, and is destroyed by the
  // host without complaint.
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 256;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  EXPECT_EQ(vkCreateBuffer(host.handles.device, &info, nullptr, &buffer), VK_SUCCESS);
  vkDestroyBuffer(host.handles.device, buffer, nullptr);
  for (const std::string& m : host.messages) ADD_FAILURE() << "validation: " << m;
}

// Fused steps per dispatch: one (memory-bound), a prime, the default.
INSTANTIATE_TEST_SUITE_P(StepsPerDispatch, Embedding, ::testing::Values(1u, 7u, 256u));

using EmbeddingDraw = test::VulkanTest;

TEST_F(EmbeddingDraw, LinesLandInAHostImageOfAnotherChannelOrder) {
  // The same lines into RGBA and BGRA targets: the same pixels, with red and blue swapped,
  // in both looks (the lava look's last pass writes the host's format).
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2500);
  const host::Submitter submitter(device());
  const OrbitCamera camera;
  for (LookStyle style : {LookStyle::Plain, LookStyle::Lava}) {
    SCOPED_TRACE(style == LookStyle::Lava ? "lava look" : "plain look");
    std::vector<uint8_t> images[2];
    const VkFormat formats[2] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM};
    for (int i = 0; i < 2; ++i) {
      host::FrameRenderer renderer(device(), formats[i], 1, style);
      const host::OffscreenTarget target(device(), {200, 150}, formats[i]);
      images[i] = host::renderOffscreen(submitter, renderer, simulation, target, camera);
    }
    size_t lit = 0;
    for (size_t p = 0; p < images[0].size(); p += 4) {
      ASSERT_EQ(images[0][p], images[1][p + 2]) << "pixel " << p / 4;
      ASSERT_EQ(images[0][p + 1], images[1][p + 1]);
      ASSERT_EQ(images[0][p + 2], images[1][p]);
      lit += images[0][p] > 120;
    }
    EXPECT_GT(lit, 100u);
  }
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

// An instance made without application info is Vulkan 1.0, which hides dynamic rendering
// from a Vulkan 1.3 device: the error must name the instance's version and what Lava needs,
// not blame the device.
TEST(EmbeddingVersions, AnInstanceOfVulkan10IsNamedAsTheProblem) {
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};  // no application info
  VkInstance instance = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateInstance(&info, nullptr, &instance), VK_SUCCESS);
  uint32_t count = 1;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  vkEnumeratePhysicalDevices(instance, &count, &physical);
  ASSERT_EQ(count, 1u);
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(physical, &properties);
  EXPECT_GE(properties.apiVersion, VK_API_VERSION_1_3) << "the pinned drivers are Vulkan 1.3+";
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queue;
  DeviceHandles handles;
  handles.instance = instance;
  handles.physicalDevice = physical;
  ASSERT_EQ(vkCreateDevice(physical, &deviceInfo, nullptr, &handles.device), VK_SUCCESS);
  vkGetDeviceQueue(handles.device, 0, 0, &handles.queue);
  try {
    Device device(handles);
    ADD_FAILURE() << "a Vulkan 1.0 instance was accepted";
  } catch (const ResourceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("instance"), std::string::npos) << what;
    EXPECT_NE(what.find("1.0"), std::string::npos) << what;
    EXPECT_NE(what.find("Vulkan 1.3"), std::string::npos) << what;
  }
  vkDestroyDevice(handles.device, nullptr);
  vkDestroyInstance(instance, nullptr);
}

}  // namespace
}  // namespace lava
