// Every Vulkan function Lava calls, loaded through the host's vkGetInstanceProcAddr (or the
// loader's) into one table per device: no global function pointers, so several devices and
// a host's own loader (volk) coexist.
#pragma once
#include <vulkan/vulkan.h>

namespace lava::detail {

// Functions of no instance (vkGetInstanceProcAddr(NULL, ...)).
#define LAVA_VK_GLOBAL(X)             \
  X(CreateInstance)                   \
  X(EnumerateInstanceLayerProperties) \
  X(EnumerateInstanceExtensionProperties)

// Instance-level functions.
#define LAVA_VK_INSTANCE(X)                  \
  X(DestroyInstance)                         \
  X(EnumeratePhysicalDevices)                \
  X(GetPhysicalDeviceProperties)             \
  X(GetPhysicalDeviceProperties2)            \
  X(GetPhysicalDeviceFeatures)               \
  X(GetPhysicalDeviceFeatures2)              \
  X(GetPhysicalDeviceMemoryProperties)       \
  X(GetPhysicalDeviceQueueFamilyProperties)  \
  X(GetPhysicalDeviceFormatProperties)       \
  X(GetPhysicalDeviceImageFormatProperties2) \
  X(EnumerateDeviceExtensionProperties)      \
  X(CreateDevice)                            \
  X(GetDeviceProcAddr)

// Device-level functions.
#define LAVA_VK_DEVICE(X)         \
  X(DestroyDevice)                \
  X(GetDeviceQueue)               \
  X(DeviceWaitIdle)               \
  X(QueueSubmit)                  \
  X(CreateBuffer)                 \
  X(DestroyBuffer)                \
  X(GetBufferMemoryRequirements)  \
  X(BindBufferMemory)             \
  X(AllocateMemory)               \
  X(FreeMemory)                   \
  X(MapMemory)                    \
  X(FlushMappedMemoryRanges)      \
  X(InvalidateMappedMemoryRanges) \
  X(CreateBufferView)             \
  X(DestroyBufferView)            \
  X(CreateImage)                  \
  X(DestroyImage)                 \
  X(GetImageMemoryRequirements)   \
  X(BindImageMemory)              \
  X(CreateImageView)              \
  X(DestroyImageView)             \
  X(CreateSampler)                \
  X(DestroySampler)               \
  X(CreateShaderModule)           \
  X(DestroyShaderModule)          \
  X(CreateDescriptorSetLayout)    \
  X(DestroyDescriptorSetLayout)   \
  X(CreateDescriptorPool)         \
  X(DestroyDescriptorPool)        \
  X(AllocateDescriptorSets)       \
  X(UpdateDescriptorSets)         \
  X(CreatePipelineLayout)         \
  X(DestroyPipelineLayout)        \
  X(CreateComputePipelines)       \
  X(CreateGraphicsPipelines)      \
  X(DestroyPipeline)              \
  X(CreateRenderPass)             \
  X(DestroyRenderPass)            \
  X(CreateFramebuffer)            \
  X(DestroyFramebuffer)           \
  X(CmdBeginRenderPass)           \
  X(CmdEndRenderPass)             \
  X(CreateCommandPool)            \
  X(DestroyCommandPool)           \
  X(AllocateCommandBuffers)       \
  X(FreeCommandBuffers)           \
  X(BeginCommandBuffer)           \
  X(EndCommandBuffer)             \
  X(CreateFence)                  \
  X(DestroyFence)                 \
  X(WaitForFences)                \
  X(CreateQueryPool)              \
  X(DestroyQueryPool)             \
  X(GetQueryPoolResults)          \
  X(CmdBindPipeline)              \
  X(CmdPushConstants)             \
  X(CmdBindDescriptorSets)        \
  X(CmdDispatch)                  \
  X(CmdPipelineBarrier)           \
  X(CmdCopyBuffer)                \
  X(CmdFillBuffer)                \
  X(CmdClearColorImage)           \
  X(CmdUpdateBuffer)              \
  X(CmdDraw)                      \
  X(CmdDrawIndirect)              \
  X(CmdResetQueryPool)            \
  X(CmdWriteTimestamp)            \
  X(CmdSetViewport)               \
  X(CmdSetScissor)

struct Vk {
#define LAVA_VK_MEMBER(name) PFN_vk##name name = nullptr;
  LAVA_VK_GLOBAL(LAVA_VK_MEMBER)
  LAVA_VK_INSTANCE(LAVA_VK_MEMBER)
  LAVA_VK_DEVICE(LAVA_VK_MEMBER)
#undef LAVA_VK_MEMBER
  PFN_vkGetInstanceProcAddr GetInstanceProcAddr = nullptr;
  // Only with the validation layer (Lava's own instance).
  PFN_vkCreateDebugUtilsMessengerEXT CreateDebugUtilsMessengerEXT = nullptr;
  PFN_vkDestroyDebugUtilsMessengerEXT DestroyDebugUtilsMessengerEXT = nullptr;
  // Only where VK_KHR_push_descriptor is enabled (DeviceContext::pushDescriptors).
  PFN_vkCmdPushDescriptorSetKHR CmdPushDescriptorSetKHR = nullptr;

  void loadGlobal(PFN_vkGetInstanceProcAddr getInstanceProcAddr);
  void loadInstance(VkInstance instance);
  // Throws ResourceError naming the first function the driver does not provide.
  void loadDevice(VkDevice device);
};

}  // namespace lava::detail
