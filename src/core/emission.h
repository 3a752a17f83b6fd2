// Host-side ring-buffer bookkeeping of SPEC §2 step 1, shared by both backends: how many
// particles each step emits, into which slots, with which serial numbers.
#pragma once
#include <cstdint>

namespace lava {

struct EmitStep {
  uint32_t head;         // first slot (re)born this step
  uint32_t count;        // slots born: head, head+1, ... mod capacity
  uint64_t firstSerial;  // serial number of the particle in slot `head`
};

struct EmissionClock {
  double accumulator = 0.0;  // fractional particles owed (SPEC: acc)
  uint64_t serial = 0;       // serial of the next particle
  uint32_t head = 0;         // next slot to (re)use
  uint64_t steps = 0;        // steps taken

  // acc += rate*h; n = floor(acc); acc -= n; n = min(n, capacity); head += n.
  EmitStep advance(double rate, float h, uint32_t capacity);
};

}  // namespace lava
