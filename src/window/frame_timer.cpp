#include "frame_timer.h"

namespace lava::window {
namespace {

uint64_t validBits(const Device& device) {
  uint32_t count = 0;
  VkPhysicalDevice physical = device.handles().physicalDevice;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
  const uint32_t bits = families.at(device.handles().queueFamily).timestampValidBits;
  return bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
}

}  // namespace

FrameTimer::FrameTimer(const Device& device, uint32_t slots)
    : device_(device),
      mask_(validBits(device)),
      msPerTick_(double(device.limits().timestampPeriod) * 1e-6),
      pending_(slots, false) {
  VkDevice handle = device.handles().device;
  VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
  queryInfo.queryCount = kStamps * slots;
  VkQueryPool pool = VK_NULL_HANDLE;
  HOST_CHECK(vkCreateQueryPool(handle, &queryInfo, nullptr, &pool));
  queries_ = host::OwnedQueryPool(handle, pool);

  VkBufferCreateInfo bufferInfo{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bufferInfo.size = sizeof(uint64_t) * kStamps * slots;
  bufferInfo.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  HOST_CHECK(vkCreateBuffer(handle, &bufferInfo, nullptr, &buffer));
  results_ = host::OwnedBuffer(handle, buffer);
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(handle, buffer, &requirements);
  const uint32_t type =
      host::memoryType(device, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                       VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  memory_ = host::allocate(device, requirements.size, type);
  coherent_ = host::coherent(device, type);
  HOST_CHECK(vkBindBufferMemory(handle, buffer, memory_, 0));
  void* mapped = nullptr;
  HOST_CHECK(vkMapMemory(handle, memory_, 0, VK_WHOLE_SIZE, 0, &mapped));
  mapped_ = static_cast<const uint64_t*>(mapped);
}

void FrameTimer::recordStart(VkCommandBuffer commands, uint32_t slot) {
  vkCmdResetQueryPool(commands, queries_, slot * kStamps, kStamps);
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, slot * kStamps);
  pending_.at(slot) = true;
}

void FrameTimer::recordSimulated(VkCommandBuffer commands, uint32_t slot) const {
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries_, slot * kStamps + 1);
}

void FrameTimer::recordEnd(VkCommandBuffer commands, uint32_t slot) const {
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, slot * kStamps + 2);
  vkCmdCopyQueryPoolResults(commands, queries_, slot * kStamps, kStamps, results_,
                            sizeof(uint64_t) * kStamps * slot, sizeof(uint64_t),
                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
  // RAW: the host reads the copied stamps once the frame's fence has signalled.
  host::memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

std::optional<FrameTimes> FrameTimer::read(uint32_t slot) {
  if (!pending_.at(slot)) return std::nullopt;
  pending_[slot] = false;
  if (!coherent_) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory_, 0,
                              VK_WHOLE_SIZE};
    HOST_CHECK(vkInvalidateMappedMemoryRanges(device_.handles().device, 1, &range));
  }
  const uint64_t* stamps = mapped_ + slot * kStamps;
  const auto ms = [this](uint64_t a, uint64_t b) {
    return double(((b & mask_) - (a & mask_)) & mask_) * msPerTick_;
  };
  return FrameTimes{ms(stamps[0], stamps[1]), ms(stamps[1], stamps[2])};
}

}  // namespace lava::window
