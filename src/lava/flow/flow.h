// The flow of docs/model.md ("The flow"): its host constants, and the CPU's step of the flow
// particles. Flow particles interact through neighbour sums taken in an order that depends on
// the state alone: the grid's buckets in order, each bucket's particles by slot, the 27 cells
// around a particle in a fixed order.
#pragma once
#include <cstdint>
#include <vector>

#include "lava/scene.h"
#include "lava/state.h"
#include "shared.h"
#include "sim/emission.h"

namespace lava::detail {

class Reference;

using gpu::kViscosityEntries;
// A pair interacts when t = 1 - r^2/radius^2 exceeds this (the kernels' tails are cut where
// their products could leave float32's normal range).
constexpr float kPairCut = 1.0f / 4096.0f;
// Pair terms below this in magnitude become 0: no denormal enters a sum.
constexpr float kTinyTerm = 0x1p-96f;
// Pairs closer than this (squared) are coincident: pushed apart along x by slot order.
constexpr float kCoincident = 1e-30f;

// The scene's flow constants, computed once in double and rounded to float32.
struct FlowConstants {
  float invRadius;         // 1 / radius: cells are radius wide
  float invRadius2;        // 1 / radius^2
  float touch2;            // (1.25 rest spacing)^2: a solid particle this close to crust touches it
  float pressure;          // c^2 (m^2/s^2), c = min(sound-speed, 0.4 radius / h)
  float solidus, temperature, ambient;
  float viscosity, viscositySolidus;  // m^2/s
  float tableScale;        // (kViscosityEntries - 1) / (temperature - solidus)
  float table[kViscosityEntries];     // viscosity from solidus (0) to temperature (last)
  float coolAir;           // h cooling-air
  float coolContact;       // h (cooling-air + cooling-ground)
  float conduction;        // 2 conduction (m^2/s)
};
FlowConstants flowConstants(const Scene& scene);

// Per emitter (zero for the others).
struct FlowWeights {
  float density;    // V / (V0 S): theta = sum of density (1 - r/radius)^3, 1 on the rest lattice
  float pressure;   // 3 density / radius (1/m): the same kernel's gradient
  float laplacian;  // h V 945 / (32 pi radius^5) (s/m^2): poly6's -W'(r)/r
  float birth;      // temperature at birth (K)
};
std::vector<FlowWeights> flowWeights(const Scene& scene);  // one per emitter

// The grid cell of a position, and its bucket among `buckets` (a power of two).
struct Cell {
  int32_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};
Cell cellOf(float x, float y, float z, float invRadius);
uint32_t bucketOf(const Cell& cell, uint32_t buckets);
// The grid's hash table size for `slots` flow slots.
uint32_t flowBuckets(uint64_t slots);

// What flow.comp reads of the scene's flow: the constants and weights above, and where each
// flow emitter's slots lie in the state and in the flow's own numbering.
gpu::FlowParams flowParams(const Scene& scene);

// The flow index of each flow emitter's first slot: its emitters' slots one after another.
struct FlowRange {
  uint64_t firstSlot;   // in the state
  uint64_t firstIndex;  // in the flow's numbering
  uint64_t count;
};
std::vector<FlowRange> flowRanges(const Scene& scene);

// The viscosity at temperature T (m^2/s): the table, interpolated; exact at both ends.
float flowViscosity(const FlowConstants& k, float temperature);

// The flow on the CPU: each step's births, then one step of every flow emitter's particles,
// over `threads` threads (the same bits for any count). Keeps its grid between steps.
class FlowStepper {
 public:
  FlowStepper(const Reference& reference, unsigned threads);
  // Step `i` of `schedule`'s births of every flow emitter (the last one landing on a slot
  // wins): emitted, at the emitter's birth temperature, not crust.
  void births(State& state, const std::vector<std::vector<Births>>& schedule, size_t i) const;
  void step(State& state);

 private:
  void sort(const State& state);
  template <class Visit>
  void neighbours(const State& state, size_t i, const Visit& visit) const;
  template <class Body>
  void parallel(size_t n, const Body& body) const;

  const Reference& reference_;
  Scene contact_;  // the scene with the flow's restitution on the ground and every collider
  FlowConstants k_;
  unsigned threads_;
  std::vector<FlowWeights> weights_;
  std::vector<uint32_t> emitterOfSlot_;  // kNotFlow for slots of other emitters
  uint32_t buckets_ = 0;
  // The grid: alive flow slots sorted by (bucket, slot); each bucket's range in `start`, and
  // the sort's next place in each (kept between steps, not reallocated).
  std::vector<uint32_t> start_, sorted_, cursor_;
  std::vector<Cell> cells_;  // per slot: its cell this step
  // Per slot, from the first pass.
  std::vector<float> theta_, pi_, viscosity_, viscous_, conductive_;
  std::vector<uint8_t> touches_;
  struct Next {
    Particle particle;
    float temperature;
    uint8_t crust;
  };
  std::vector<Next> next_;  // the step's results, in sorted order, written back at its end
};

}  // namespace lava::detail
