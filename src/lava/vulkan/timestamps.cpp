#include "timestamps.h"

#include <vector>

#include "common/check.h"

namespace lava::detail {

uint64_t timestampMask(const DeviceContext& c) {
  uint32_t count = 0;
  c.vk.GetPhysicalDeviceQueueFamilyProperties(c.handles.physicalDevice, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  c.vk.GetPhysicalDeviceQueueFamilyProperties(c.handles.physicalDevice, &count, families.data());
  const uint32_t bits =
      c.handles.queueFamily < count ? families[c.handles.queueFamily].timestampValidBits : 64;
  if (bits == 0) throw ResourceError("this device's queue has no timestamps");
  return bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
}

TimestampPair::TimestampPair(const DeviceContext& c) : context_(c), mask_(timestampMask(c)) {
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2;
  VkQueryPool pool = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateQueryPool(c.device(), &info, c.allocator(), &pool));
  pool_ = UniqueQueryPool(c, pool);
}

void TimestampPair::recordStart(VkCommandBuffer commands) const {
  context_.vk.CmdResetQueryPool(commands, pool_, 0, 2);
  context_.vk.CmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 0);
}

void TimestampPair::recordEnd(VkCommandBuffer commands) const {
  context_.vk.CmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, 1);
}

double TimestampPair::seconds() const {
  uint64_t stamps[2] = {0, 0};
  VK_CHECK(context_.vk.GetQueryPoolResults(context_.device(), pool_, 0, 2, sizeof(stamps), stamps,
                                           sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const uint64_t ticks = ((stamps[1] & mask_) - (stamps[0] & mask_)) & mask_;
  return double(ticks) * double(context_.limits.timestampPeriod) * 1e-9;
}

}  // namespace lava::detail
