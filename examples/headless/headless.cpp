// The smallest host of Lava: a device of its own, the simulation recorded into its own
// command buffer and submitted on its own queue, the result checked against Lava's CPU
// reference. Exit status 0 when they agree bit for bit. It links Lava::lava_tools (pkg-config:
// lava_tools) for lava::compare, and Lava::lava through it.
#include <lava/lava.h>
#include <lava/validation.h>  // lava::compare, in Lava::lava_tools

#include <cstdio>

namespace {

// A minimal instance and device with what Lava asks for (no error handling beyond checks).
struct Host {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE] = "";
};

bool createHost(Host& host) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instanceInfo.pApplicationInfo = &app;
  if (vkCreateInstance(&instanceInfo, nullptr, &host.instance) != VK_SUCCESS) return false;
  uint32_t count = 1;
  vkEnumeratePhysicalDevices(host.instance, &count, &host.physical);
  if (count == 0) return false;
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(host.physical, &properties);
  std::snprintf(host.name, sizeof host.name, "%s", properties.deviceName);
  const lava::DeviceRequirements needs = lava::deviceRequirements(properties.apiVersion);
  VkPhysicalDeviceDynamicRenderingFeatures dynamic{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
  dynamic.dynamicRendering = VK_TRUE;
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = 0;  // lavapipe and most GPUs: graphics and compute
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.pNext = &dynamic;
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  deviceInfo.enabledExtensionCount = static_cast<uint32_t>(needs.extensions.size());
  deviceInfo.ppEnabledExtensionNames = needs.extensions.data();
  if (vkCreateDevice(host.physical, &deviceInfo, nullptr, &host.device) != VK_SUCCESS) return false;
  vkGetDeviceQueue(host.device, 0, 0, &host.queue);
  return true;
}

}  // namespace

int main() {
  Host host;
  if (!createHost(host)) return 1;
  const VkDevice vkDevice = host.device;
  int status = 1;
  try {
    lava::Device device(lava::DeviceHandles{host.instance, host.physical, vkDevice, 0, host.queue});
    // The crater of the lab handout, three times as busy; scene files read the same way.
    const lava::Scene scene = lava::parseScene("rate = 3000\n", "inline scene");
    lava::GpuSimulationOptions options;
    options.maxStepsPerFrame = 1000;
    lava::GpuSimulation simulation(device, scene, options);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    VkCommandPool pool = VK_NULL_HANDLE;
    vkCreateCommandPool(vkDevice, &poolInfo, nullptr, &pool);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(vkDevice, &alloc, &cmd);
    for (int batch = 0; batch < 3; ++batch) {  // 3 x 1000 steps, each its own submission
      simulation.update(0, 1000);
      VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
      vkBeginCommandBuffer(cmd, &begin);
      simulation.recordSimulate(cmd, 0);
      vkEndCommandBuffer(cmd);
      VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
      submit.commandBufferCount = 1;
      submit.pCommandBuffers = &cmd;
      vkQueueSubmit(host.queue, 1, &submit, VK_NULL_HANDLE);
      vkQueueWaitIdle(host.queue);
    }
    lava::CpuSimulation reference(scene);
    reference.advance(3000);
    const lava::Comparison c =
        lava::compare(simulation.state().particles, reference.state().particles);
    std::printf("headless: lava %s on %s: %llu/%llu slots bit-identical after 3000 steps\n",
                lava::versionString(), host.name,
                static_cast<unsigned long long>(c.equal),
                static_cast<unsigned long long>(c.particles));
    status = c.equal == c.particles ? 0 : 1;
    vkDestroyCommandPool(vkDevice, pool, nullptr);
  } catch (const lava::Error& e) {
    std::fprintf(stderr, "headless: %s\n", e.what());
  }
  vkDestroyDevice(vkDevice, nullptr);
  vkDestroyInstance(host.instance, nullptr);
  return status;
}
