// The GPU time of a frame's simulation and draw, from three timestamps per frame slot that
// the frame's own commands copy into host-visible memory. They are read once the slot's
// fence has signalled, so no frame waits on vkGetQueryPoolResults: lavapipe drains the
// whole queue there, which kept the demo at one frame in flight. Only some frames are
// timed (the caller chooses): on lavapipe each timestamp is a pass of the rasteriser's
// threads over every tile.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "host/vulkan.h"

namespace lava::window {

struct FrameTimes {
  double simulateMs = 0.0;
  double drawMs = 0.0;
};

class FrameTimer {
 public:
  FrameTimer(const Device& device, uint32_t slots);
  FrameTimer(const FrameTimer&) = delete;
  FrameTimer& operator=(const FrameTimer&) = delete;

  void recordStart(VkCommandBuffer commands, uint32_t slot);  // this frame is timed
  void recordSimulated(VkCommandBuffer commands, uint32_t slot) const;
  void recordEnd(VkCommandBuffer commands, uint32_t slot) const;  // stamps and copies them
  // Once the slot's fence has signalled: its last frame's times if that frame was timed and
  // they were not read yet.
  std::optional<FrameTimes> read(uint32_t slot);

 private:
  static constexpr uint32_t kStamps = 3;  // start, after the simulation, after the draw
  host::OwnedQueryPool queries_;
  host::ReadbackBuffer results_;  // the stamps, kStamps per slot
  uint64_t mask_;                 // the queue's valid timestamp bits
  double msPerTick_;
  std::vector<bool> pending_;  // per slot: a timed frame's stamps not read yet
};

}  // namespace lava::window
