#include "emission.h"

#include <algorithm>
#include <cmath>

namespace lava {

EmitStep EmissionClock::advance(double rate, float h, uint32_t capacity) {
  accumulator += rate * static_cast<double>(h);
  double whole = std::floor(accumulator);
  accumulator -= whole;
  uint32_t count = static_cast<uint32_t>(std::min(whole, static_cast<double>(capacity)));
  EmitStep step{head, count, serial};
  head = static_cast<uint32_t>((static_cast<uint64_t>(head) + count) % capacity);
  serial += count;
  ++steps;
  return step;
}

}  // namespace lava
