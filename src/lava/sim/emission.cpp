#include "emission.h"

#include <algorithm>
#include <cmath>

namespace lava::detail {

uint64_t burstPeriod(const Emitter& e, double dt) {
  if (e.burstInterval <= 0.0) return 0;
  return std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(e.burstInterval / dt)));
}

Births advanceClock(EmitterClock& clock, const Emitter& e, float h, uint64_t period,
                    uint64_t step) {
  double births = 0.0;
  if (e.burst > 0 && (step == 0 || (period > 0 && step % period == 0))) births = e.burst;
  clock.accumulator += e.rate * static_cast<double>(h);
  const double whole = std::floor(clock.accumulator);
  clock.accumulator -= whole;
  const uint32_t count =
      static_cast<uint32_t>(std::min(births + whole, static_cast<double>(e.particles)));
  const Births out{clock.head, count, clock.serial};
  clock.head = static_cast<uint32_t>((uint64_t{clock.head} + count) % e.particles);
  clock.serial += count;
  return out;
}

}  // namespace lava::detail
