// What both CPU flows share (cpu_flow.cpp, the explicit flow; cpu_implicit.cpp, the implicit
// one): the float helpers both write in flow.comp's order, the rest lattice's sums, and the
// FlowStepper's neighbour loop and threads. Included by those two files only, which are built
// with -ffp-contract=off.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "flow.h"
#include "sim/model-inl.h"
#include "sim/reference.h"

namespace lava::detail::flowcpu {

using Model = scalar::Model<float>;
using V = Model::V3;

constexpr uint32_t kNotFlow = std::numeric_limits<uint32_t>::max();
constexpr double kPi = 3.14159265358979323846;

inline float tiny(float term) {
  return std::fabs(term) < kTinyTerm ? 0.0f : term;
}

// 1/q from 1/sqrt(q) squared: multiplications only, the same bits everywhere.
inline float reciprocal(float q) {
  const float y = Model::inverseRoot(q);
  return y * y;
}

// At most 1: the factor that keeps a particle's exchange rates summing to at most 1/2.
inline float stable(float rate) {
  return rate > 0.5f ? 0.5f * reciprocal(rate) : 1.0f;
}

// The rest spacing and volume of the first flow emitter's particles.
inline double restVolume(const Scene& scene) {
  for (const Emitter& e : scene.emitters)
    if (e.flow) return double(e.mass) / double(scene.flow->density);
  const double half = 0.5 * double(scene.flow->radius);
  return half * half * half;
}

// visit(a, b, c, r) for every site (a, b, c) spacing of the cubic lattice around a point
// (itself included) that is a pair (t > kPairCut), r its distance.
template <class Visit>
void forLattice(double spacing, double radius, const Visit& visit) {
  const int n = int(std::ceil(radius / spacing));
  for (int a = -n; a <= n; ++a)
    for (int b = -n; b <= n; ++b)
      for (int c = -n; c <= n; ++c) {
        const double q = spacing * spacing * double(a * a + b * b + c * c);
        if (1.0 - q / (radius * radius) <= double(kPairCut)) continue;
        visit(a, b, c, std::sqrt(q));
      }
}

// The sum of (1 - r/radius)^3 over the rest lattice around a point, itself included.
inline double latticeSum(double spacing, double radius) {
  double sum = 0.0;
  forLattice(spacing, radius, [&](int, int, int, double r) {
    const double u = 1.0 - r / radius;
    sum += u * u * u;
  });
  return sum;
}

// The distance r of a pair and its unit direction n from j to i: coincident pairs (no
// direction) are pushed apart along x, the lower slot towards -x.
inline float distance(float q, const V& d, uint32_t i, uint32_t j, V& n) {
  if (!(q >= kCoincident)) {
    n = V{i < j ? -1.0f : 1.0f, 0.0f, 0.0f};
    return 0.0f;
  }
  const float inv = Model::inverseRoot(q);
  n = inv * d;
  return q * inv;
}

// After a flow particle's move: a NaN or infinity dies with x = v = 0 (docs/model.md
// "Non-finite values"); otherwise the ground and the colliders of `contact`, and a solid they
// moved becomes crust there. Crust stops: v = 0. Returns whether a solid moved it.
inline bool settle(const Scene& contact, const Reference& reference, const V& x0, bool liquid,
                   V& x, V& v, bool& becomesCrust, bool& dies) {
  bool touched = false;
  if (!becomesCrust && Model::nonFinite(x, v)) {
    x = v = V{0.0f, 0.0f, 0.0f};
    dies = true;
  } else if (!becomesCrust) {
    float lost = 0.0f;
    touched = Model::contact(contact, reference, x0, x, v, lost, true);
    dies = lost < 0.0f;
    becomesCrust = !liquid && touched;
  }
  if (becomesCrust) v = V{0.0f, 0.0f, 0.0f};
  return touched;
}

// The end of a flow particle's step of h: T' = (T + dT) - cool (T - ambient) and its age; a
// death, or a lifetime spent, leaves an unborn slot (age -1, T 0, no crust).
inline void finish(const Emitter& emitter, float ambient, float h, float cool, float age0,
                   float temperature, float dT, bool dies, float& age, float& t1,
                   bool& becomesCrust) {
  t1 = (temperature + dT) - cool * (temperature - ambient);
  age = age0 + h;
  if (dies || (emitter.lifetime > 0.0f && age >= emitter.lifetime)) {
    age = -1.0f;
    t1 = 0.0f;
    becomesCrust = false;
  }
}

}  // namespace lava::detail::flowcpu

namespace lava::detail {

// Calls bucket(n, begin, count, centre) for the 27 cells n around c, z then y then x from
// -1 to +1: [begin, begin + count) are n's bucket's entries (sorted_, entries_), centre
// whether n is c.
template <class Bucket>
void FlowStepper::aroundCell(const Cell& c, const Bucket& bucket) const {
  for (int32_t dz = -1; dz <= 1; ++dz)
    for (int32_t dy = -1; dy <= 1; ++dy)
      for (int32_t dx = -1; dx <= 1; ++dx) {
        const Cell n{c.x + dx, c.y + dy, c.z + dz};
        const uint32_t b = bucketOf(n, buckets_);
        bucket(n, start_[b], start_[b + 1] - start_[b], dx == 0 && dy == 0 && dz == 0);
      }
}

// Calls visit(j, d, q, t) for every flow particle j within the radius of particle i (i
// itself included): the cells around its own (aroundCell), each bucket's first bucketCap_
// slots in order, and i after them when its own bucket holds it beyond them.
template <class Visit>
void FlowStepper::neighbours(const State& state, size_t i, const Visit& visit) const {
  using flowcpu::V;
  const Particle& p = state.particles[i];
  const Cell c = cells_[i];
  aroundCell(c, [&](const Cell& n, uint32_t begin, uint32_t count, bool centre) {
    uint32_t reads = std::min(count, bucketCap_);
    if (count > bucketCap_ && centre && i > sorted_[begin + bucketCap_ - 1]) ++reads;
    for (uint32_t r = 0; r < reads; ++r) {
      const bool own = r == bucketCap_;  // i itself, beyond the bucket's first bucketCap_
      const Entry o = own ? Entry{p.px, p.py, p.pz, c} : entries_[begin + r];
      if (!(o.cell == n)) continue;
      const uint32_t j = own ? uint32_t(i) : sorted_[begin + r];
      const V d{p.px - o.x, p.py - o.y, p.pz - o.z};
      const float q = dot(d, d);
      const float t = 1.0f - q * k_.invRadius2;
      if (t > kPairCut) visit(j, d, q, t);
    }
  });
}

// range(begin, end) over [0, n) in chunks, over the stepper's threads (Workers::forEach):
// each chunk exactly once, and the results each element's own, whichever thread takes it.
template <class Range>
void FlowStepper::ranges(size_t n, const Range& range) const {
  if (n < 2048 || workers_.size() == 1) {
    range(size_t(0), n);
    return;
  }
  workers_.forEach(n, range);
}

// body(e) for e in [0, n), over the stepper's threads: each e writes only its own results,
// so the threads change no bit, whichever thread takes it.
template <class Body>
void FlowStepper::parallel(size_t n, const Body& body) const {
  ranges(n, [&](size_t begin, size_t end) {
    for (size_t e = begin; e < end; ++e) body(e);
  });
}

}  // namespace lava::detail
