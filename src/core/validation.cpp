#include "validation.h"

#include <algorithm>

namespace lava {
namespace {

bool identical(const Comparison& c) {
  return c.equal == c.particles;
}

// From `agreed` (bitwise equal in both), one step at a time until they differ; at most to
// step `limit`, which is known to differ.
uint64_t replay(Simulator& subject, Simulator& reference, const SimState& agreed, uint64_t limit) {
  subject.load(agreed);
  reference.load(agreed);
  for (uint64_t step = agreed.clock.steps + 1; step < limit; ++step) {
    subject.advance(1);
    reference.advance(1);
    if (!identical(compare(subject.state().particles, reference.state().particles))) return step;
  }
  return limit;
}

}  // namespace

ValidationReport validateBackends(Simulator& subject, Simulator& reference, uint64_t steps,
                                  uint64_t every, uint32_t toleranceUlp,
                                  const std::function<void(const Checkpoint&)>& onCheckpoint) {
  ValidationReport report;
  SimState agreed = reference.state();
  for (uint64_t step = agreed.clock.steps, end = step + steps; step < end;) {
    const uint64_t batch = std::min(every, end - step);
    subject.advance(batch);
    reference.advance(batch);
    step += batch;
    SimState ours = subject.state(), theirs = reference.state();
    const Checkpoint checkpoint{step, compare(ours.particles, theirs.particles)};
    report.checkpoints.push_back(checkpoint);
    if (onCheckpoint) onCheckpoint(checkpoint);
    report.pass = report.pass && checkpoint.comparison.maxUlp <= toleranceUlp;
    if (identical(checkpoint.comparison)) {
      agreed = std::move(theirs);
    } else if (!report.firstDivergentStep) {
      report.firstDivergentStep = replay(subject, reference, agreed, step);
      subject.load(ours);
      reference.load(theirs);
    }
  }
  return report;
}

}  // namespace lava
