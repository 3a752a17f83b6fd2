// The Vulkan device Lava works on: the host's own handles, borrowed (Lava never destroys
// them), or an instance and device Lava creates itself (the `lava` program, tests).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "export.h"

namespace lava {

namespace detail {
struct DeviceContext;
}

// The host's handles. The device must have been created with what deviceRequirements()
// lists. Lava records into command buffers of `queueFamily` and submits its blocking
// helpers to `queue` (the host must not use that queue from another thread meanwhile).
// Lifetimes: the instance, physical device, device, queue, allocator and pipeline cache are
// used for as long as the Device and anything made on it exist (pipelines are built after
// construction too); enabledFeatures only during the Device constructor.
struct DeviceHandles {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;  // graphics and compute
  VkQueue queue = VK_NULL_HANDLE;
  // Optional: how Lava loads every Vulkan function (e.g. volk's); default: the loader's.
  PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
  // Optional: passed to every create and destroy call Lava makes.
  const VkAllocationCallbacks* allocator = nullptr;
  // Optional: used for every pipeline Lava creates.
  VkPipelineCache pipelineCache = VK_NULL_HANDLE;
  // Optional: the device was created with shaderInt64 and shaderBufferInt64Atomics (see
  // DeviceRequirements): the splat then adds two pixels per atomic. For a device Lava
  // created, whether it enabled them.
  bool int64Atomics = false;
  // Optional: the device was created with VK_KHR_push_descriptor: Lava pushes its
  // descriptors instead of writing sets from pools of its own. For a device Lava created,
  // whether it enabled it.
  bool pushDescriptors = false;
  // Optional: the feature chain the device was created with (VkDeviceCreateInfo::pNext, or
  // pEnabledFeatures wrapped in one). Vulkan cannot report a device's enabled features, so
  // with this Lava checks them: dynamic rendering, and shaderInt64 and
  // shaderBufferInt64Atomics when int64Atomics is set (InvalidArgument naming the feature).
  // Read only in the Device constructor.
  const VkPhysicalDeviceFeatures2* enabledFeatures = nullptr;
  // Whether the device was created with dynamic rendering (see DeviceRequirements). A host
  // that draws only into render passes may leave it off; then give every LineRenderer and
  // Backdrop a render pass (RenderFormats::renderPass).
  bool dynamicRendering = true;
  // The host's frames in flight: how many fences guard its frames (see
  // Device::setFramesInFlight), 1 to 16.
  uint32_t framesInFlight = 2;
  // Optional: the VkApplicationInfo::apiVersion the instance was created with, which Vulkan
  // cannot report (0: not given). Given, Device checks it before any other call: below 1.2
  // is InvalidArgument naming VkApplicationInfo::apiVersion. Not given, an instance older
  // than 1.2 is found only by what it hides, after Vulkan 1.1 calls the validation layer
  // reports.
  uint32_t instanceApiVersion = 0;
};

// What a device must offer Lava: create it with these (vk-bootstrap or by hand).
struct DeviceRequirements {
  // The lowest VkApplicationInfo::apiVersion of the host's instance (1.2): the instance's
  // version caps what Lava sees of the device. A Vulkan 1.3 device under a 1.2 instance needs
  // VK_KHR_dynamic_rendering enabled like a 1.2 device (deviceRequirements(VK_API_VERSION_1_2)
  // lists it); an older instance hides dynamic rendering, and Device names its version.
  uint32_t instanceApiVersion = 0;
  std::vector<const char*> extensions;  // device extensions to enable
  // VkPhysicalDeviceVulkan13Features::dynamicRendering (or
  // VkPhysicalDeviceDynamicRenderingFeatures): the device must offer it; enable it unless
  // Lava draws only into render passes (DeviceHandles::dynamicRendering).
  bool dynamicRendering = false;
  // Optional, where the device offers them: VkPhysicalDeviceFeatures::shaderInt64 and
  // shaderBufferInt64Atomics (Vulkan 1.2), then DeviceHandles::int64Atomics = true.
  bool int64Atomics = false;
  // Optional, where the device offers them (then set DeviceHandles::pushDescriptors):
  // VK_KHR_push_descriptor.
  std::vector<const char*> optionalExtensions;
};
// For a physical device of Vulkan version `deviceApiVersion` (1.2 needs the dynamic
// rendering extension, 1.3 has it in core), without asking it: int64Atomics is true and
// optionalExtensions lists every optional extension; enable those the device offers.
LAVA_API DeviceRequirements deviceRequirements(uint32_t deviceApiVersion = VK_API_VERSION_1_3);
// For this physical device, asked: int64Atomics only where it offers both features,
// optionalExtensions only those it offers; `getInstanceProcAddr` as in DeviceHandles. It
// makes Vulkan 1.0 calls only, so it is safe on any instance, and its instanceApiVersion
// says what Lava needs. `instanceApiVersion`: as DeviceHandles::instanceApiVersion (0: not
// given); below 1.2 is InvalidArgument naming VkApplicationInfo::apiVersion, before any call.
LAVA_API DeviceRequirements deviceRequirements(VkInstance instance, VkPhysicalDevice physical,
                                               PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr,
                                               uint32_t instanceApiVersion = 0);

// How Lava creates a device of its own.
struct DeviceOptions {
  std::optional<unsigned> index;                // physical device index; else discrete, integrated,
                                                // virtual GPU, then CPU, the first of the best kind
  bool validation = false;                      // the Khronos validation layer with synchronization
                                                // validation; messages via takeValidationMessages()
  std::vector<const char*> instanceExtensions;  // required, e.g. a window system's
  std::vector<const char*> deviceExtensions;    // enabled where the device offers them
  // Optional paths, each taken where the device offers it; false takes the fallback even
  // there (a profile of a device that lacks it, for tests):
  bool int64Atomics = true;     // 64-bit buffer atomics (the splat adds two pixels at once)
  bool pushDescriptors = true;  // VK_KHR_push_descriptor (else descriptor sets)
  bool floatControls = true;    // declare RTE rounding and signed-zero preservation
  std::string applicationName = "lava";
  uint32_t framesInFlight = 2;  // see Device::setFramesInFlight
};

struct DeviceSummary {
  unsigned index;
  std::string name;
  VkPhysicalDeviceType type;
  uint32_t apiVersion;
};

// Thread safety: takeValidationMessages() may be called from any thread. Distinct objects
// made on one Device may be built, used for recording and destroyed on distinct threads at
// once (each records only into the command buffer it is given, and owns its descriptor
// pools); two GpuSimulations on two threads are tested. The blocking helpers of all of them
// share the Device's command pool and submit to its queue: one at a time, and not while
// the host uses that queue on another thread.
class LAVA_API Device {
 public:
  // Creates an instance and a device (throws ResourceError when there is no driver, no
  // device or no suitable queue; InvalidArgument "device" for an index not listed).
  explicit Device(const DeviceOptions& options = {});
  // Borrows the host's (throws ResourceError when the physical device cannot run Lava).
  explicit Device(const DeviceHandles& borrowed);
  // Own device: waits until it is idle, then destroys it. Borrowed: waits on nothing and
  // destroys only what Lava made (its command pool); destroy Lava's objects on it first,
  // each once the host's work that uses it has finished.
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceHandles& handles() const;
  bool ownsHandles() const;
  const VkPhysicalDeviceProperties& properties() const;
  const VkPhysicalDeviceLimits& limits() const;
  // "llvmpipe: Mesa 22.3.6 (LLVM 15.0.6)": the driver's name and version text.
  std::string driver() const;
  // The float controls Lava's shaders rely on, in words ("RTE rounding: yes, ...").
  std::string floatControls() const;
  // The optional paths this device takes, in words: "push descriptors: yes, ...".
  std::string optionalPaths() const;
  // Whether Lava enabled `extension` (own device) or the device offers it (borrowed).
  bool hasExtension(const char* extension) const;

  VkDeviceSize deviceLocalBytes() const;    // the largest device-local heap
  VkDeviceSize maxAllocationBytes() const;  // the largest single allocation
  uint32_t particlesPerChunk() const;       // particles one buffer (binding, dispatch) holds
  uint64_t maxParticles() const;            // the most particles a simulation may have here

  // Own device: every device the instance listed, and the index of the one in use.
  const std::vector<DeviceSummary>& candidates() const;
  unsigned index() const;

  // Frame slots: the host records frame after frame, each guarded by one of its fences, and
  // names the frame's slot in GpuSimulation::update()/recordSimulate() and LineRenderer's
  // recordPrepare()/recordDraw() by the index of that fence (0 .. framesInFlight() - 1),
  // not by the swapchain image's index: drivers hand out images in any order (lavapipe
  // always the same one), and a slot is reused only once its fence has signalled. The count
  // is the device's, so every simulation and renderer on it agrees; a slot index at or past
  // it throws InvalidArgument ("frame"). Change it when the host's count changes (a rebuilt
  // swapchain with more images): objects grow their per-slot resources on the next use of
  // a new slot; a lower count keeps them. 1 to 16 (InvalidArgument "framesInFlight"); not
  // while another thread records with an object on this device.
  void setFramesInFlight(uint32_t count);
  uint32_t framesInFlight() const;

  // Validation messages (errors and warnings) since the last call; own device only.
  std::vector<std::string> takeValidationMessages();
  // Blocking: waits until the device is idle.
  void waitIdle() const;
  // Blocking: `record` records into a one-time command buffer of the Device's pool, which is
  // then submitted on its queue and waited on (a blocking helper: see Thread safety). For
  // work outside the host's frames: uploads, offscreen frames, read-backs.
  void submitNow(const std::function<void(VkCommandBuffer)>& record) const;

  detail::DeviceContext& context() const { return *context_; }

 private:
  std::unique_ptr<detail::DeviceContext> context_;
};

}  // namespace lava
