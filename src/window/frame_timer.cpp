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
    : results_(device, sizeof(uint64_t) * kStamps * slots),
      mask_(validBits(device)),
      msPerTick_(double(device.limits().timestampPeriod) * 1e-6),
      pending_(slots, false) {
  VkDevice handle = device.handles().device;
  VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
  queryInfo.queryCount = kStamps * slots;
  VkQueryPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateQueryPool(handle, &queryInfo, nullptr, &pool));
  queries_ = host::OwnedQueryPool(handle, pool);
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
  vkCmdCopyQueryPoolResults(commands, queries_, slot * kStamps, kStamps, results_.buffer(),
                            sizeof(uint64_t) * kStamps * slot, sizeof(uint64_t),
                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
  // RAW: the host reads the copied stamps once the frame's fence has signalled.
  host::memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

std::optional<FrameTimes> FrameTimer::read(uint32_t slot) {
  if (!pending_.at(slot)) return std::nullopt;
  pending_[slot] = false;
  const uint64_t* stamps = static_cast<const uint64_t*>(results_.read()) + slot * kStamps;
  const auto ms = [this](uint64_t a, uint64_t b) {
    return double(((b & mask_) - (a & mask_)) & mask_) * msPerTick_;
  };
  return FrameTimes{ms(stamps[0], stamps[1]), ms(stamps[1], stamps[2])};
}

}  // namespace lava::window
