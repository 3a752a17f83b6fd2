// The flow of docs/model.md ("The flow"): its host constants, and the CPU's step of the flow
// particles. Flow particles interact through neighbour sums taken in an order that depends on
// the state alone: the grid's buckets in order, each bucket's particles by slot, the 27 cells
// around a particle in a fixed order.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lava/scene.h"
#include "lava/state.h"
#include "shared.h"
#include "sim/emission.h"
#include "internal.h"
#include "flow/workers.h"

namespace lava::detail {

class Reference;

struct V3f {
  float x, y, z;
};

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
  // The implicit flow's: the Laplacian's weight without h, scaled to be exact on the rest
  // lattice (1/m^2), and the particle's volume in V0.
  float viscous, volume;
};

// The implicit flow's limits (docs/model.md, "The implicit flow").
constexpr uint32_t kMaxSubsteps = 16;          // a step's most substeps
constexpr uint32_t kViscousIterations = 64;    // the viscosity's most CG iterations
constexpr uint32_t kPressureIterations = 64;   // the density constraint's most CG iterations
// The most neighbours a particle keeps: twice the rest lattice's of the lightest flow
// emitter, at least kLeastNeighbourCap and at most kMostNeighbourCap (a radius of 5 spacings).
constexpr uint32_t kLeastNeighbourCap = 64;
constexpr uint32_t kMostNeighbourCap = 1024;

// The implicit flow's constants, computed once in double and rounded to float32.
struct ImplicitConstants {
  float phi, slope;   // a solid's density at distance d: phi u^5 (3 - 2u), its d-derivative
                      // slope u^4 (5 - 4u), u = 1 - d/radius
  float epsilon;      // the constraint's relaxation, added to its gradients' squares (1/m^2)
  float restDegree;   // the rest lattice's sum of t^2 over a particle's neighbours
  float tolerance2;   // the CG stops where r.z <= tolerance2 b.(b / D), per component
  float pressureTolerance2;  // and the density constraint's where r.z <= this b.(b / D)
  float near;         // a particle this close to a solid (m) touches it: rest spacing
  float coolAir, coolContact;  // 1/s
  float invStep;               // 1 / the scene's step (1/s)
  float cfl2[kMaxSubsteps];    // (n 0.4 s0)^2 (m^2) for n = 1..: n substeps move at most that
  float inverse[kMaxSubsteps]; // 1/n
  uint32_t cap;                // the most neighbours a particle keeps (above)
  uint32_t bucketCap;          // the most entries a neighbour search reads of a bucket: twice
                               // a cell's sites at rest ((radius/spacing)^3), at least flow.comp's
};
ImplicitConstants implicitConstants(const Scene& scene);
std::vector<FlowWeights> flowWeights(const Scene& scene);  // one per emitter

// The grid cell of a position, and its bucket among `buckets` (a power of two).
struct Cell {
  int32_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};
LAVA_INTERNAL Cell cellOf(float x, float y, float z, float invRadius);
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
LAVA_INTERNAL std::vector<FlowRange> flowRanges(const Scene& scene);

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
  void killNonFinite(State& state) const;
  void sort(const State& state);
  // The explicit flow's two passes (docs/model.md): the density ratios and exchange rates,
  // then the forces and each particle's move into next_, from the start-of-step state.
  void explicitRates(const State& state);
  void explicitMove(const State& state);
  // The implicit flow (cpu_implicit.cpp): substeps of a fraction of the step each.
  void implicitStep(State& state);
  void substep(State& state, float fraction, uint32_t substeps);
  void arrange();
  void gatherNeighbours(const State& state, float hs);
  struct Found;
  void gatherPairs(const State& state, uint32_t f, const Found& pairs, float hs, float conduction);
  void forces(const State& state, float fraction);
  void viscousSystem(float hs);
  void solveViscosity();
  void multiplyViscous();
  // hs m_f viscous_j (nu_f + nu_j): times a pair's weights, its share of f's row.
  float viscousCoefficient(uint32_t f, uint32_t j, float hs) const;
  void densitySystem(const State& state, float hs, float invHs);
  // The density constraint's CGs run side by side (solveConstraints): a product, or a
  // correction, takes one or two lanes at once, lane k's multipliers m[k] into its own
  // buffers (u_[lane[k]], w_[lane[k]], aq_[lane[k]]).
  template <unsigned N>
  using Multipliers = std::array<const std::vector<float>*, N>;
  template <unsigned N>
  using Lanes = std::array<unsigned, N>;
  template <unsigned N>
  void multiplyDensity(const Multipliers<N>& x, const Lanes<N>& lane);
  template <unsigned N>
  void correction(const Multipliers<N>& m, const Lanes<N>& lane);  // w = S u, u = -J^T m
  // w = S u on the liquid particles: the density constraint's velocity changes smoothed.
  template <unsigned N>
  void smooth(const Lanes<N>& lane);
  void smoothingWeights();
  void solveConstraints(float hs, float limit);
  void solveDensity(const State& state, float hs, float invHs);
  float conducted(const State& state, uint32_t f, float conduction) const;
  // d theta_f / dt of each lane's velocities u[k].
  template <unsigned N>
  std::array<float, N> rateOf(uint32_t f, const std::array<const std::vector<V3f>*, N>& u) const;
  float pressureOf(uint32_t f) const;  // the pressure weight of the particle at place f
  void move(State& state, float hs, float fraction, float invHs);
  template <class Visit>
  void walls(float x, float y, float z, const Visit& visit) const;
  template <class Bucket>
  void aroundCell(const Cell& c, const Bucket& bucket) const;
  template <class Visit>
  void neighbours(const State& state, size_t i, const Visit& visit) const;
  // The entries a particle of one cell reads in a neighbour search, in neighbours()' order:
  // the same for all the cell's particles, so that the implicit flow gathers them once per
  // cell (27 hash lookups and scattered loads), not once per particle.
  struct Candidates {
    Cell cell{0, 0, 0};
    bool filled = false;  // whether cell's candidates are those below
    std::vector<float> x, y, z;
    std::vector<uint32_t> slot;
    uint32_t centreEnd = 0;  // the centre bucket's last candidate, plus one
    // Whether the centre bucket holds more than bucketCap_ entries, and its last one read:
    // a particle beyond it visits itself after the centre bucket's candidates.
    bool overflows = false;
    uint32_t centreLast = 0;
  };
  void candidates(const Cell& c, Candidates& out) const;
  // Particle i's pairs from its cell's candidates, in neighbours()' order: each one's slot,
  // d = x_i - x_j, q = |d|^2 and t as there, and its distance r and unit direction n as
  // distance() gives them, computed for all the pairs in one loop rather than in each
  // pair's visit, where their chain of dependent operations kept the core waiting.
  struct Found {
    std::vector<uint32_t> slot;
    std::vector<float> dx, dy, dz, q, t, r, nx, ny, nz;
    uint32_t count = 0;
  };
  void found(const State& state, size_t i, const Candidates& near, Found& out) const;
  template <class Body>
  void parallel(size_t n, const Body& body) const;
  template <class Range>
  void ranges(size_t n, const Range& range) const;
  template <unsigned K, class Term>
  std::array<float, K> orderedSums(const Term& term) const;
  template <unsigned K>
  std::array<float, K> termSums() const;

  const Reference& reference_;
  Scene contact_;  // the scene with the flow's restitution on the ground and every collider
  FlowConstants k_;
  mutable Workers workers_;  // the passes' threads, started once for the stepper's life
  std::vector<FlowWeights> weights_;
  std::vector<uint32_t> emitterOfSlot_;  // kNotFlow for slots of other emitters
  uint32_t buckets_ = 0;
  // The most entries a neighbour search reads of a bucket: flow.comp's for the explicit flow,
  // ImplicitConstants::bucketCap for the implicit one.
  uint32_t bucketCap_ = gpu::kFlowBucketCap;
  // The grid: alive flow slots sorted by (bucket, slot); each bucket's range in `start`, and
  // the sort's next place in each (kept between steps, not reallocated).
  std::vector<uint32_t> start_, sorted_, cursor_;
  std::vector<Cell> cells_;  // per slot: its cell this step
  // Per entry of sorted_: its slot's position and cell, so that a neighbour search reads a
  // bucket's candidates from consecutive memory rather than each from its slot.
  struct Entry {
    float x, y, z;
    Cell cell;
  };
  std::vector<Entry> entries_;
  // Per slot, from the first pass.
  std::vector<float> theta_, pi_, viscosity_, viscous_, conductive_;
  std::vector<uint8_t> touches_;
  struct Next {
    Particle particle;
    float temperature;
    uint8_t crust;
  };
  std::vector<Next> next_;  // the step's results, in sorted order, written back at its end

  // The implicit flow's, per slot unless named per flow index or place.
  ImplicitConstants ik_{};
  std::vector<uint32_t> flowSlots_;  // per flow index: its slot
  // The substep's values are kept per place (arrange()): its slot in at_, each flow index's
  // place in place_; keys_ the Z-order sort's.
  std::vector<uint32_t> at_, place_, indexAt_;  // indexAt_: per place, its flow index
  std::vector<uint64_t> keys_;
  // Each place's pairs (at most ik_.cap) in three arrays, by the passes that read them: the
  // solvers' products read only links, the constraint's also slopes, so that a CG iteration
  // streams 8 or 24 bytes a pair rather than all 36.
  struct Link {
    uint32_t j;  // the neighbour's place
    // The pass's weight (0 for a solid j): S's, t^2 min(1/d_i, 1/d_j), in the density
    // constraint; then the viscosity's, its coupling times j's viscous coefficient (A's entry).
    float weight;
  };
  struct Slope {
    V3f e;           // (1 - r/radius)^2 times the unit direction from j to i
    float pressure;  // j's pressure weight
  };
  // The products load e as 16 bytes (cpu_implicit.cpp, X3): they must stay in the pair's.
  static_assert(sizeof(Slope) == 16 && offsetof(Slope, e) == 0, "e's 16 bytes are the Slope");
  struct Kernel {
    float t2;  // (1 - r^2/radius^2)^2
    // The viscosity's weights: t^2 plus its images' t^2 across the solids near i (each image
    // moving at 2 friction - 1 times v_j): on i's diagonal, and on its coupling to j.
    float diagonal, coupling;
  };
  std::vector<Link> links_;
  std::vector<Slope> slopes_;
  std::vector<Kernel> kernels_;
  Link* linksOf(size_t f) { return &links_[first_[f]]; }
  const Link* linksOf(size_t f) const { return &links_[first_[f]]; }
  Slope* slopesOf(size_t f) { return &slopes_[first_[f]]; }
  const Slope* slopesOf(size_t f) const { return &slopes_[first_[f]]; }
  Kernel* kernelsOf(size_t f) { return &kernels_[first_[f]]; }
  const Kernel* kernelsOf(size_t f) const { return &kernels_[first_[f]]; }
  std::vector<uint32_t> count_;       // per place: its pairs
  // Per place: its first pair. A chunk of the neighbour pass, places [b, e), keeps their pairs
  // one after another from b cap: the passes stream them without the gaps of cap a place.
  std::vector<size_t> first_;
  std::vector<uint32_t> indexOf_;     // per slot: its place (kNotFlow for others)
  // Per place: what the substep's neighbour pass found, and the solvers' values.
  struct Own {
    float nu;           // viscosity (m^2/s)
    float theta;        // density ratio, solids' share included
    float invG;         // 1 / (hs (|grad theta|^2 + moving neighbours' |g|^2 + epsilon))
    float wallViscous;  // its own images' t^2 across the solids, each times 2 - 2 friction
    float conductive;   // the conduction's stability factor
    float diag, invDiag;
    float invDegree;    // S's: 1 / max(sum of t^2 over liquid neighbours, restDegree)
    float total;  // the density constraint's multiplier (m^2/s)
    uint8_t liquid, touches, near, active;
  };
  std::vector<Own> own_;
  // gradWall: the solids' share of grad theta; v: the velocity being solved (the viscosity's
  // CG solves into it); r, z, p, q, b: the CG's residual, preconditioned residual,
  // direction, A p and right side.
  std::vector<V3f> gradWall_, v_, r_, z_, p_, q_, b_;
  std::vector<float> pressure_;  // the substep's results, written back with next_
  // The density constraint's multipliers and right side; each of its two CGs' residual,
  // preconditioned residual, direction and product; u the velocity change of a product,
  // w it smoothed.
  std::vector<float> lambda_, rhs_, ar_[2], az_[2], ap_[2], aq_[2];
  std::vector<V3f> u_[2], w_[2];
  // The constraint's positions' share: its multipliers and right side, and the substep's
  // move it makes besides the velocity (a pseudo-velocity, m/s).
  std::vector<float> lambdaP_, rhsP_;
  std::vector<V3f> pseudo_;
  // Per flow index: the terms of a CG's dot products, left by the pass that computes them
  // (each place writes its own), summed in order on one thread (termSums).
  std::vector<V3f> terms_;
};

}  // namespace lava::detail
