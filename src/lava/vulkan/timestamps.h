// GPU time between two points of a command buffer, from timestamp queries (masked to the
// queue's valid bits, scaled by the device's timestamp period).
#pragma once
#include "device_context.h"
#include "unique.h"
#include "internal.h"

namespace lava::detail {

class LAVA_INTERNAL TimestampPair {
 public:
  explicit TimestampPair(const DeviceContext& context);
  void recordStart(VkCommandBuffer commands) const;  // resets the pair, then stamps
  void recordEnd(VkCommandBuffer commands) const;    // after everything recorded before
  double seconds() const;                            // once the submission finished

 private:
  const DeviceContext& context_;
  UniqueQueryPool pool_;
  uint64_t mask_;
};

// The valid-bits mask of timestamps on the context's queue family (all ones for 64).
uint64_t timestampMask(const DeviceContext& context);

}  // namespace lava::detail
