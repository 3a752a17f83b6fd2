// In liblava_tools (Lava::lava_tools, pkg-config lava_tools), beside liblava.
// Comparing two backends: particle states side by side, and a run of both compared at
// checkpoints that names the first step at which they differ (`lava validate`).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "export.h"
#include "simulation.h"
#include "state.h"

namespace lava {

// Distance in units in the last place between two floats: 0 when bitwise equal, 1 between
// +0 and -0 and between neighbours; the largest value when exactly one is NaN (two NaNs
// count as equal only when their bits are).
LAVA_TOOLS_API uint32_t ulpDistance(float a, float b);

// The first differing float of the first differing slot.
struct Difference {
  uint64_t particle = 0;  // slot index in the state
  uint32_t emitter = 0;   // the emitter that slot belongs to (when a scene was given)
  uint32_t field = 0;     // 0..9: px py pz age vx vy vz mass, then a flow's temperature crust
  uint32_t subjectBits = 0;
  uint32_t referenceBits = 0;
};
LAVA_TOOLS_API const char* fieldName(uint32_t field);

struct Comparison {
  uint64_t particles = 0;           // slots compared
  uint64_t equal = 0;               // slots bitwise identical (all 8 floats, and a flow's
                                    // temperature and crust flag)
  uint64_t alive = 0;               // slots alive in the reference
  float maxDx = 0.0f;               // largest |difference| of a position component (m)
  float maxDv = 0.0f;               // largest |difference| of a velocity component (m/s)
  uint32_t maxUlp = 0;              // largest ULP distance of any float
  std::optional<Difference> first;  // none when equal == particles
};

LAVA_TOOLS_API Comparison compare(const std::vector<Particle>& subject,
                            const std::vector<Particle>& reference);
// The same, naming each difference's emitter.
LAVA_TOOLS_API Comparison compare(const Scene& scene, const std::vector<Particle>& subject,
                            const std::vector<Particle>& reference);
// Whole states: the particles, and for a scene with a flow each slot's temperature and crust
// flag too.
LAVA_TOOLS_API Comparison compare(const Scene& scene, const State& subject, const State& reference);

struct Checkpoint {
  uint64_t step;  // steps since the run began
  Comparison comparison;
  uint64_t subjectHash = 0;    // stateHash() of each side's state
  uint64_t referenceHash = 0;
};

struct ValidationReport {
  std::vector<Checkpoint> checkpoints;
  std::optional<uint64_t> firstDivergentStep;  // none: bitwise equal at every step checked
  std::optional<Difference> firstDifference;   // at that step
  bool pass = true;                            // every checkpoint within the tolerance
};

// Blocking (through both simulations' blocking helpers): advances both `every` steps at a
// time for `steps` steps, comparing at each checkpoint.
// On the first difference it replays the last agreeing interval one step at a time to
// name the first divergent step, then carries on from where each backend was, so later
// checkpoints show the accumulated divergence. Both must start from the same state.
LAVA_TOOLS_API ValidationReport validate(Simulation& subject, Simulation& reference, uint64_t steps,
                                   uint64_t every, uint32_t toleranceUlp,
                                   const std::function<void(const Checkpoint&)>& onCheckpoint = {});

}  // namespace lava
