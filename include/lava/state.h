// A simulation's state: every slot's particle and every emitter's emission clock. The same
// type for both backends, so a state moves between them (and to a file) bit for bit.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "export.h"
#include "scene.h"

namespace lava {

// One slot, 32 bytes: exactly the layout of the GPU's particle buffers (two vec4).
struct Particle {
  float px, py, pz;  // position (m)
  float age;         // s since emission; < 0: not alive (never emitted, or dead)
  float vx, vy, vz;  // velocity (m/s)
  float mass;        // kg
};
static_assert(sizeof(Particle) == 32, "Particle is two vec4");

// One emitter's ring bookkeeping.
struct EmitterClock {
  double accumulator = 0.0;  // fractional births owed
  uint64_t serial = 0;       // serial number of the next particle born
  uint32_t head = 0;         // next slot to be reborn, relative to the emitter's first slot
};

struct State {
  uint64_t step = 0;                 // steps taken since the run began (bursts count from it)
  std::vector<EmitterClock> clocks;  // one per emitter
  std::vector<Particle> particles;   // Scene::particles() slots: emitter 0's, then 1's, ...
  // Scenes with a flow (Scene::flow), one per slot; empty otherwise:
  std::vector<float> temperature;  // K: flow particles'; 0 for other slots and unborn ones
  std::vector<uint8_t> crust;      // 1: a crust particle (stopped for good until reborn)
  // Scenes with an implicit flow (FlowSolver::Implicit), one per slot; empty otherwise: a
  // liquid flow particle's pressure at its last substep (m^2/s^2), where the next begins.
  std::vector<float> pressure;
};

// Before the first step: every slot unborn (zero position and velocity, age -1, mass 0;
// temperature 0, not crust).
LAVA_API State initialState(const Scene& scene);
// Throws InvalidArgument ("particles") when the scene's state, and one copy of it, would not
// fit in the host memory still available (the kernel's estimate, or the control group's
// limit): refused up front, never a failed allocation hours into a run. initialState() and
// with it every backend's constructor check it.
LAVA_API void checkHostMemory(const Scene& scene);

// Throws InvalidArgument ("state: ...") unless `state` fits `scene`: as many particles as
// its slots, one clock per emitter, each head inside its ring, temperatures and crust flags
// for each slot exactly when the scene has a flow, and pressures when that flow is implicit.
LAVA_API void checkState(const Scene& scene, const State& state);

// A 64-bit FNV-1a-style hash of the particles' bytes: equal states, equal hashes, on any
// machine (Lava's own offset basis; see sim/state.cpp).
LAVA_API uint64_t stateHash(const std::vector<Particle>& particles);
// The particles' hash, continued over each slot's temperature and crust flag when the state
// has them (a scene with a flow), then its pressures (an implicit flow): a state without a
// flow hashes as its particles.
LAVA_API uint64_t stateHash(const State& state);

// Which emitter slot `slot` belongs to.
LAVA_API size_t emitterOf(const Scene& scene, uint64_t slot);

}  // namespace lava
