// The CPU reference of SPEC §2, written apart from the shader, in plain float32 C++ built
// with -ffp-contract=off so that it and a conforming driver agree bit for bit.
#pragma once
#include "simulator.h"

namespace lava {

// One particle through one step; `born` says the host's schedule (re)emits it now.
void stepParticle(const Scene& scene, Particle& particle, bool born, uint64_t serial);

class CpuSimulator final : public Simulator {
 public:
  // threads == 0: all hardware threads.
  explicit CpuSimulator(const Scene& scene, unsigned threads = 1);
  void advance(uint64_t steps) override;
  SimState state() override { return state_; }
  void load(const SimState& state) override { state_ = state; }
  unsigned threads() const { return threads_; }

 private:
  void runRange(const std::vector<EmitStep>& schedule, size_t begin, size_t end);

  SimState state_;
  unsigned threads_;
};

}  // namespace lava
