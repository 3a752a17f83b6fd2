// What every Lava object needs of its device: the function table, the handles (owned or
// borrowed), the properties and limits Lava reads, a command pool for blocking helpers.
// `limits` and the allocation figures are copies, so tests can impose another vendor's.
#pragma once
#include <vulkan/vulkan.h>

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include "api.h"
#include "lava/device.h"
#include "internal.h"

namespace lava::detail {

struct LAVA_INTERNAL DeviceContext {
  Vk vk;
  DeviceHandles handles;
  bool owned = false;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  std::vector<DeviceSummary> candidates;
  unsigned index = 0;
  std::vector<std::string> extensions;  // enabled (own device) or offered (borrowed)

  VkPhysicalDeviceProperties properties{};
  VkPhysicalDeviceLimits limits{};  // what Lava sizes things by
  VkPhysicalDeviceMemoryProperties memory{};
  VkPhysicalDeviceDriverProperties driver{};
  VkPhysicalDeviceFloatControlsProperties floatControls{};
  VkDeviceSize maxAllocation = 0;        // min(maxMemoryAllocationSize, largest heap)
  VkDeviceSize deviceLocal = 0;          // the largest device-local heap
  VkDeviceSize hostImportAlignment = 0;  // VK_EXT_external_memory_host, 0 when not enabled
  bool pushDescriptors = false;          // VK_KHR_push_descriptor enabled: no descriptor sets
  std::atomic<uint32_t> framesInFlight{2};  // Device::setFramesInFlight

  VkCommandPool pool = VK_NULL_HANDLE;  // for blocking helpers

  std::mutex messagesMutex;
  std::vector<std::string> messages;

  VkDevice device() const { return handles.device; }
  const VkAllocationCallbacks* allocator() const { return handles.allocator; }
  bool hasExtension(const char* name) const;
  // InvalidArgument ("frame") unless `frame` is one of the device's frame slots.
  void checkFrame(uint32_t frame) const;
  // A memory type among `typeBits` with all of `required`, preferring one that also has
  // `preferred`; throws ResourceError when none has `required`.
  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred = 0) const;

  // Blocking: a one-time command buffer recorded by `record`, submitted, waited on.
  template <typename Record>
  void submitNow(Record&& record) const {
    VkCommandBuffer commands = beginOneShot();
    try {
      record(commands);
    } catch (...) {
      vk.FreeCommandBuffers(handles.device, pool, 1, &commands);
      throw;
    }
    submitAndWait(commands);
  }
  VkCommandBuffer beginOneShot() const;
  void submitAndWait(VkCommandBuffer commands) const;  // frees `commands`

  // Reads the physical device's properties, limits and memory into this context.
  void describe();
  // Creates the command pool (both constructors, last).
  void createPool();
  // Destroys what Lava created (and, when owned, the device and instance).
  void release();
};

}  // namespace lava::detail
