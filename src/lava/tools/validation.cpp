// Two backends run side by side and compared at checkpoints.
#include <algorithm>

#include "lava/validation.h"

namespace lava {
namespace {

bool identical(const Comparison& c) {
  return c.equal == c.particles;
}

// From `agreed` (bitwise equal in both), one step at a time until they differ; at most to
// step `limit`, which is known to differ. Returns the step and its first difference.
std::pair<uint64_t, std::optional<Difference>> replay(Simulation& subject, Simulation& reference,
                                                      const State& agreed, uint64_t limit) {
  subject.setState(agreed);
  reference.setState(agreed);
  for (uint64_t step = agreed.step + 1; step <= limit; ++step) {
    subject.advance(1);
    reference.advance(1);
    const Comparison c = compare(reference.scene(), subject.state(), reference.state());
    if (!identical(c) || step == limit) return {step, c.first};
  }
  return {limit, std::nullopt};
}

}  // namespace

ValidationReport validate(Simulation& subject, Simulation& reference, uint64_t steps,
                          uint64_t every, uint32_t toleranceUlp,
                          const std::function<void(const Checkpoint&)>& onCheckpoint) {
  ValidationReport report;
  every = std::max<uint64_t>(every, 1);
  State agreed = reference.state();
  for (uint64_t step = agreed.step, end = step + steps; step < end;) {
    const uint64_t batch = std::min(every, end - step);
    subject.advance(batch);
    reference.advance(batch);
    step += batch;
    State ours = subject.state(), theirs = reference.state();
    const Checkpoint checkpoint{step, compare(reference.scene(), ours, theirs), stateHash(ours),
                                stateHash(theirs)};
    report.checkpoints.push_back(checkpoint);
    if (onCheckpoint) onCheckpoint(checkpoint);
    report.pass = report.pass && checkpoint.comparison.maxUlp <= toleranceUlp;
    if (identical(checkpoint.comparison)) {
      agreed = std::move(theirs);
    } else if (!report.firstDivergentStep) {
      const auto [first, difference] = replay(subject, reference, agreed, step);
      report.firstDivergentStep = first;
      report.firstDifference = difference ? difference : checkpoint.comparison.first;
      subject.setState(ours);
      reference.setState(theirs);
    }
  }
  return report;
}

}  // namespace lava
