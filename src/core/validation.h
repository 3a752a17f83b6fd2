// Two backends run side by side and compared at checkpoints, as `lava validate` reports
// it: per-checkpoint differences and the first step at which they differ.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "compare.h"
#include "simulator.h"

namespace lava {

struct Checkpoint {
  uint64_t step;
  Comparison comparison;
};

struct ValidationReport {
  std::vector<Checkpoint> checkpoints;
  std::optional<uint64_t> firstDivergentStep;  // none: bitwise equal at every step checked
  bool pass = true;                            // every checkpoint within the ULP tolerance
};

// Advances both `every` steps at a time to `steps`, comparing at each checkpoint. On the
// first difference it replays the last agreeing interval one step at a time to name the
// first divergent step, then puts each backend back where it was, so later checkpoints show
// the accumulated divergence. Both must start from the same state.
ValidationReport validateBackends(Simulator& subject, Simulator& reference, uint64_t steps,
                                  uint64_t every, uint32_t toleranceUlp,
                                  const std::function<void(const Checkpoint&)>& onCheckpoint = {});

}  // namespace lava
