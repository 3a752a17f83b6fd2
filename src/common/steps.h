// A fixed step decoupled from the frame rate: each frame owes a fractional number of steps,
// takes the whole ones and carries the fraction to the next (the demo and `lava render`).
#pragma once
#include <cmath>
#include <cstdint>

namespace lava::common {

class StepAccumulator {
 public:
  // Adds `steps` owed and returns the whole steps to take now.
  uint64_t take(double steps) {
    owed_ += steps;
    const double whole = std::floor(owed_);
    owed_ -= whole;
    return static_cast<uint64_t>(whole);
  }
  void reset() { owed_ = 0.0; }

 private:
  double owed_ = 0.0;
};

}  // namespace lava::common
