// GPU time between two points of a command buffer, from timestamp queries.
#pragma once
#include "context.h"

namespace lava {

class TimestampPair {
 public:
  explicit TimestampPair(const Context& context);
  void recordStart(VkCommandBuffer commands) const;  // resets the pair, then stamps
  void recordEnd(VkCommandBuffer commands) const;    // after everything recorded before
  double seconds() const;                            // once the submission finished

 private:
  const Context& context_;
  UniqueQueryPool pool_;
};

}  // namespace lava
