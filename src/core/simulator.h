// The common face of the two backends: a ring buffer of particles plus its emission clock,
// advanced step by step as SPEC §2 says.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "emission.h"
#include "scene.h"
#include "shared.h"

namespace lava {

using gpu::Particle;

struct SimState {
  std::vector<Particle> particles;  // one per ring slot
  EmissionClock clock;
};

// Every slot unborn: zero position and velocity, age -1, mass 0.
SimState initialState(const Scene& scene);

class Simulator {
 public:
  virtual ~Simulator() = default;
  virtual void advance(uint64_t steps) = 0;
  virtual SimState state() = 0;
  virtual void load(const SimState& state) = 0;
  const Scene& scene() const { return scene_; }

 protected:
  explicit Simulator(const Scene& scene) : scene_(scene) {}
  Scene scene_;
};

}  // namespace lava
