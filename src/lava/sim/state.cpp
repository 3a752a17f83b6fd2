// States: the initial one, the check that a state fits a scene, and its hash.
#include <cstring>

#include "common/hash.h"
#include "lava/error.h"
#include "lava/state.h"

namespace lava {

State initialState(const Scene& scene) {
  State state;
  state.clocks.assign(scene.emitters.size(), EmitterClock{});
  state.particles.assign(scene.particles(), Particle{0, 0, 0, -1.0f, 0, 0, 0, 0});
  if (scene.flow) {
    state.temperature.assign(scene.particles(), 0.0f);
    state.crust.assign(scene.particles(), 0);
  }
  return state;
}

void checkState(const Scene& scene, const State& state) {
  if (state.particles.size() != scene.particles())
    throw InvalidArgument("state", "has " + std::to_string(state.particles.size()) +
                                       " particles; the scene has " +
                                       std::to_string(scene.particles()) + " slots");
  if (state.clocks.size() != scene.emitters.size())
    throw InvalidArgument("state", "has " + std::to_string(state.clocks.size()) +
                                       " emitter clocks; the scene has " +
                                       std::to_string(scene.emitters.size()) + " emitters");
  const size_t flowSlots = scene.flow ? state.particles.size() : 0;
  if (state.temperature.size() != flowSlots || state.crust.size() != flowSlots)
    throw InvalidArgument("state", "has " + std::to_string(state.temperature.size()) +
                                       " temperatures and " + std::to_string(state.crust.size()) +
                                       " crust flags; the scene " +
                                       (scene.flow ? "has a flow of " + std::to_string(flowSlots) +
                                                         " slots"
                                                   : std::string("has no flow")));
  for (size_t k = 0; k < state.clocks.size(); ++k)
    if (state.clocks[k].head >= scene.emitters[k].particles)
      throw InvalidArgument("state", "emitter " + std::to_string(k) + "'s head " +
                                         std::to_string(state.clocks[k].head) +
                                         " lies outside its ring of " +
                                         std::to_string(scene.emitters[k].particles));
}

uint64_t stateHash(const std::vector<Particle>& particles) {
  return common::fnv1a(common::kStateHashOffset, particles.data(),
                       particles.size() * sizeof(Particle));
}

uint64_t stateHash(const State& state) {
  uint64_t hash = stateHash(state.particles);
  if (!state.temperature.empty())
    hash = common::fnv1a(hash, state.temperature.data(), state.temperature.size() * sizeof(float));
  if (!state.crust.empty()) hash = common::fnv1a(hash, state.crust.data(), state.crust.size());
  return hash;
}

}  // namespace lava
