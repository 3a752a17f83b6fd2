// The GPU time of each frame's simulation and draw, from three timestamps per frame slot
// that the frame's own commands copy into host-visible memory. They are read once the
// slot's fence has signalled, so no frame waits on vkGetQueryPoolResults: lavapipe drains
// the whole queue there, which kept the demo at one frame in flight.
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

  void recordStart(VkCommandBuffer commands, uint32_t slot);  // resets the slot's stamps
  void recordSimulated(VkCommandBuffer commands, uint32_t slot) const;
  void recordEnd(VkCommandBuffer commands, uint32_t slot) const;  // stamps and copies them
  // The slot's last frame's times, once its fence has signalled; none before its first.
  std::optional<FrameTimes> read(uint32_t slot) const;

 private:
  static constexpr uint32_t kStamps = 3;  // start, after the simulation, after the draw
  const Device& device_;
  host::OwnedQueryPool queries_;
  host::OwnedBuffer results_;
  host::OwnedMemory memory_;
  bool coherent_ = false;
  const uint64_t* mapped_ = nullptr;
  uint64_t mask_;  // the queue's valid timestamp bits
  double msPerTick_;
  std::vector<bool> recorded_;  // per slot: a frame's stamps were recorded
};

}  // namespace lava::window
