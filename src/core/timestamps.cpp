#include "timestamps.h"

#include "vk_check.h"

namespace lava {

TimestampPair::TimestampPair(const Context& context) : context_(context) {
  if (context.limits().timestampComputeAndGraphics == VK_FALSE)
    throw ResourceError(std::string("device '") + context.properties().deviceName +
                        "' has no timestamps on its queue");
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2;
  VkQueryPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &pool));
  pool_ = UniqueQueryPool(context.device(), pool);
}

void TimestampPair::recordStart(VkCommandBuffer commands) const {
  vkCmdResetQueryPool(commands, pool_, 0, 2);
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 0);
}

void TimestampPair::recordEnd(VkCommandBuffer commands) const {
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, 1);
}

double TimestampPair::seconds() const {
  uint64_t stamps[2] = {0, 0};
  VK_CHECK(vkGetQueryPoolResults(context_.device(), pool_, 0, 2, sizeof(stamps), stamps,
                                 sizeof(uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  return double(stamps[1] - stamps[0]) * double(context_.limits().timestampPeriod) * 1e-9;
}

}  // namespace lava
