// The Vulkan instance, the chosen physical device, one logical device with one queue, and
// the validation messages the layer reported (when enabled).
#pragma once
#include <vulkan/vulkan.h>

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "unique.h"

namespace lava {

struct ContextOptions {
  bool validation = false;              // enable VK_LAYER_KHRONOS_validation (throws if missing)
  bool syncValidation = false;          // also its synchronization validation
  std::optional<unsigned> deviceIndex;  // explicit choice; else LAVA_DEVICE, else the best
  std::vector<const char*> instanceExtensions;  // e.g. from glfwGetRequiredInstanceExtensions
  bool swapchain = false;                       // enable VK_KHR_swapchain on the device
  bool hostImport = false;  // enable VK_EXT_external_memory_host where the device has it
};

struct DeviceSummary {
  unsigned index;
  std::string name;
  VkPhysicalDeviceType type;
  VkPhysicalDeviceProperties properties;
};

const char* deviceTypeName(VkPhysicalDeviceType type);

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  VkCommandPool commandPool() const { return pool_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  unsigned deviceIndex() const { return deviceIndex_; }
  const std::vector<DeviceSummary>& devices() const { return devices_; }

  // Largest VkDeviceMemory this device gives: min(maxMemoryAllocationSize, largest heap).
  VkDeviceSize maxAllocationSize() const { return maxAllocation_; }
  // Size of the largest device-local memory heap.
  VkDeviceSize deviceMemory() const { return deviceMemory_; }
  // Whether buffers can use host memory in place (VK_EXT_external_memory_host enabled), and
  // the alignment of such a pointer and size (0 when not).
  VkDeviceSize hostImportAlignment() const { return hostImportAlignment_; }
  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags wanted) const;

  // Allocates a primary command buffer, records it with `record`, submits and waits.
  template <typename Record>
  void submitNow(Record&& record) const;
  VkCommandBuffer beginOneShot() const;
  void submitAndWait(VkCommandBuffer commands) const;

  // Messages the validation layer reported since the last take (errors and warnings).
  std::vector<std::string> takeValidationMessages();

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT types,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* self);
  void pickDevice(const ContextOptions& options);
  void release();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::vector<DeviceSummary> devices_;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  unsigned deviceIndex_ = 0;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDeviceSize maxAllocation_ = 0;
  VkDeviceSize deviceMemory_ = 0;
  VkDeviceSize hostImportAlignment_ = 0;
  uint32_t queueFamily_ = 0;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::mutex messagesMutex_;
  std::vector<std::string> messages_;
};

template <typename Record>
void Context::submitNow(Record&& record) const {
  VkCommandBuffer commands = beginOneShot();
  record(commands);
  submitAndWait(commands);
}

}  // namespace lava
