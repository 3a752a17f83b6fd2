// The host's ring bookkeeping (docs/model.md, "Emission"), shared by both backends: how many
// particles each emitter bears in a step, into which of its slots, with which serials.
#pragma once
#include <cstdint>

#include "lava/scene.h"
#include "lava/state.h"

namespace lava::detail {

struct Births {
  uint32_t head;         // first slot born, relative to the emitter's first slot
  uint32_t count;        // slots born: head, head + 1, ... mod capacity
  uint64_t firstSerial;  // serial of the particle born into `head`
};

// Steps between bursts: round(burstInterval / dt), at least 1; 0 for a step-0-only burst.
uint64_t burstPeriod(const Emitter& emitter, double dt);

// Births of emitter `e` in step `step` (counted from the run's first step, 0): a burst
// when due, then acc += rate * h; m = floor(acc); acc -= m; n = min(burst + m, capacity).
// Advances `clock`.
Births advanceClock(EmitterClock& clock, const Emitter& e, float h, uint64_t period, uint64_t step);

}  // namespace lava::detail
