// States: the initial one, the check that a state fits a scene, and its hash.
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>

#include "common/hash.h"
#include "lava/error.h"
#include "lava/state.h"

namespace lava {

namespace {

// The host memory this process may still take (bytes): the kernel's estimate of what can be
// allocated without swapping, lowered to the control group's limit when one is set.
uint64_t availableHostMemory() {
  uint64_t available = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGESIZE));
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    uint64_t kib = 0;
    meminfo >> kib;
    if (key == "MemAvailable:") available = kib * 1024;
    meminfo.ignore(256, '\n');
  }
  std::ifstream limit("/sys/fs/cgroup/memory.max");
  uint64_t cap = 0;
  if (limit >> cap && cap > 0) available = std::min(available, cap);
  return available;
}

bool implicitFlow(const Scene& scene) {
  return scene.flow && scene.flow->solver == FlowSolver::Implicit;
}

}  // namespace

void checkHostMemory(const Scene& scene) {
  // A state and one copy of it (what state() returns), each slot's particle and, with a
  // flow, its temperature and crust flag.
  const uint64_t perSlot = sizeof(Particle) + (scene.flow ? sizeof(float) + 1 : 0) +
                          (implicitFlow(scene) ? sizeof(float) : 0);
  const uint64_t need = 2 * scene.particles() * perSlot;
  const uint64_t available = availableHostMemory();
  if (need > available)
    throw InvalidArgument("particles", std::to_string(scene.particles()) + " particles need " +
                                           std::to_string(need >> 20) +
                                           " MiB of host memory for their state; this machine "
                                           "has " +
                                           std::to_string(available >> 20) + " MiB available");
}

State initialState(const Scene& scene) {
  checkHostMemory(scene);
  State state;
  state.clocks.assign(scene.emitters.size(), EmitterClock{});
  state.particles.assign(scene.particles(), Particle{0, 0, 0, -1.0f, 0, 0, 0, 0});
  if (scene.flow) {
    state.temperature.assign(scene.particles(), 0.0f);
    state.crust.assign(scene.particles(), 0);
  }
  if (implicitFlow(scene)) state.pressure.assign(scene.particles(), 0.0f);
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
  const size_t pressures = implicitFlow(scene) ? state.particles.size() : 0;
  if (state.pressure.size() != pressures)
    throw InvalidArgument("state", "has " + std::to_string(state.pressure.size()) +
                                       " pressures; the scene's flow needs " +
                                       std::to_string(pressures));
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
  if (!state.pressure.empty())
    hash = common::fnv1a(hash, state.pressure.data(), state.pressure.size() * sizeof(float));
  return hash;
}

}  // namespace lava
