// The CPU backend over the rings: the host's emission schedule, then reference.cpp's
// particle step (or simd.cpp's on lanes), for blocks of particles at a time, split over the
// threads asked for.
#include <algorithm>
#include <cmath>
#include <thread>

#include <optional>

#include "emission.h"
#include "flow/flow.h"
#include "lava/error.h"
#include "lava/simulation.h"
#include "reference.h"
#include "simd.h"

namespace lava {

namespace {

constexpr uint64_t kScheduleBatch = 4096;  // steps whose emission is planned at once

}  // namespace

std::string cpuSimdTarget(const std::string& target) {
  return detail::simdTarget(detail::simdTargetNamed(target));
}

std::vector<std::string> cpuSimdTargets() {
  return detail::simdTargets();
}

CpuSimulation::CpuSimulation(const Scene& scene, unsigned threads, CpuKernel kernel,
                             const std::string& simdTarget)
    : Simulation(scene),
      state_(initialState(scene)),
      threads_(std::max(threads, 1u)),
      kernel_(kernel),
      simdTarget_(detail::simdTargetNamed(simdTarget)) {
  if (kernel_ == CpuKernel::Simd) detail::simdTarget(0);  // finds the best once, before threads
}

struct CpuSimulation::Steppers {
  Steppers(const Scene& scene, unsigned threads) : reference(scene) {
    if (scene.flows()) flow.emplace(reference, threads);
  }
  detail::Reference reference;
  std::optional<detail::FlowStepper> flow;  // reads reference
};

CpuSimulation::~CpuSimulation() = default;
CpuSimulation::CpuSimulation(CpuSimulation&&) noexcept = default;
CpuSimulation& CpuSimulation::operator=(CpuSimulation&&) noexcept = default;

void CpuSimulation::setScene(const Scene& scene) {
  Simulation::setScene(scene);
  steppers_.reset();
}

std::string CpuSimulation::simdTarget() const {
  return kernel_ == CpuKernel::Simd ? detail::simdTarget(simdTarget_) : "";
}

std::string CpuSimulation::name() const {
  return (kernel_ == CpuKernel::Simd ? "cpu-simd " + simdTarget() : "cpu reference") + ", " +
         std::to_string(threads_) + (threads_ == 1 ? " thread" : " threads") +
         (kernel_ == CpuKernel::Simd && scene_.flows() ? ", the flow on the scalar kernel" : "");
}

void CpuSimulation::setState(const State& state) {
  checkState(scene_, state);
  state_ = state;
}

namespace {

// Each emitter's births for the next `batch` steps, its clock advanced past them, and the
// state's step with them.
void planBirths(const Scene& scene, float h, uint64_t batch, State& state,
                std::vector<std::vector<detail::Births>>& schedule) {
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    const Emitter& e = scene.emitters[k];
    const uint64_t period = detail::burstPeriod(e, scene.dt);
    schedule[k].clear();
    for (uint64_t i = 0; i < batch; ++i)
      schedule[k].push_back(detail::advanceClock(state.clocks[k], e, h, period, state.step + i));
  }
  state.step += batch;
}

}  // namespace

void CpuSimulation::advance(uint64_t steps) {
  const float h = scene_.h();
  if (!steppers_) steppers_ = std::make_unique<Steppers>(scene_, threads_);
  const detail::Reference& reference = steppers_->reference;
  std::optional<detail::FlowStepper>& flow = steppers_->flow;
  std::vector<std::vector<detail::Births>> schedule(scene_.emitters.size());
  while (steps > 0) {
    const uint64_t batch = std::min(steps, kScheduleBatch);
    planBirths(scene_, h, batch, state_, schedule);

    // A block of particles goes through the steps together: their independent dependency
    // chains overlap in the CPU's pipeline, and the block stays in L1.
    // cpu-simd: the block is moved into lanes once for the whole batch of steps.
    auto run = [&](uint64_t begin, uint64_t end) {
      const bool simd = kernel_ == CpuKernel::Simd;
      const uint64_t blockSize = simd ? detail::kSimdBlock : detail::kReferenceBlock;
      for (uint64_t first = begin; first < end;) {
        const size_t k = emitterOf(scene_, first);
        const uint64_t base = scene_.firstSlot(k);
        if (scene_.emitters[k].flow) {  // stepped together below
          first = std::min(end, base + scene_.emitters[k].particles);
          continue;
        }
        const uint64_t n =
            std::min({blockSize, end - first, base + scene_.emitters[k].particles - first});
        const uint32_t slot = static_cast<uint32_t>(first - base);
        if (simd) {
          detail::simdRun(reference, simdTarget_, k, schedule[k], slot, &state_.particles[first],
                          n);
        } else {
          Particle block[detail::kReferenceBlock];
          std::copy_n(&state_.particles[first], n, block);
          reference.run(k, schedule[k], slot, block, n);
          std::copy_n(block, n, &state_.particles[first]);
        }
        first += n;
      }
    };
    const uint64_t n = state_.particles.size();
    if (threads_ == 1 || n < 4096) {
      run(0, n);
    } else {
      std::vector<std::thread> workers;
      for (unsigned t = 0; t < threads_; ++t)
        workers.emplace_back([&, t] { run(n * t / threads_, n * (t + 1) / threads_); });
      for (std::thread& w : workers) w.join();
    }
    // The flow particles interact: all of them go through each step together.
    for (uint64_t i = 0; flow && i < batch; ++i) {
      flow->births(state_, schedule, i);
      flow->step(state_);
    }
    steps -= batch;
  }
}

}  // namespace lava
