// The implicit flow on the CPU (docs/model.md, "The implicit flow"). A step is cut into
// substeps by a CFL bound; each substep finds every particle's neighbours once, applies the
// forces, projects the velocities onto the density constraint (conjugate gradients, its
// velocity changes smoothed; the share that undoes compression moves the positions only),
// then solves the viscosity implicitly (a Jacobi-preconditioned conjugate gradient per
// component), and moves. Its values are kept along the Z-order curve of the cells
// (arrange()); every sum runs in an order fixed by the state (flow index order for the CGs'
// dot products), in plain float32 built with -ffp-contract=off: gathers only, the same bits
// for any thread count.
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "flow.h"
#include "flow/stepper-inl.h"
#include "sim/constants.h"
#include "sim/reference.h"

namespace lava::detail {
namespace {

using namespace flowcpu;
using flowcpu::tiny;

constexpr uint32_t kBlock = gpu::kWorkgroupSize;
// The density constraint's relaxation: a fraction of the rest lattice's squared gradients.
constexpr double kRelax = 1e-6;
// The CFL bound: a substep moves no particle more than this many rest spacings. At 0.4 the
// eruption took 1.5 times as long and no published solution moved by a point; the dam break
// at 1/120 s holds its front at 1.0 and explodes at 1.2 (docs/flow.md).
constexpr double kCourant = 0.8;
// The viscosity's CG stops once every component's residual is this small beside its right
// side: tighter changes no published solution's deviation by a percent (docs/flow.md).
constexpr float kTolerance = 1e-3f;
// A liquid particle whose predicted theta is within this of 1 is in the bulk: pressed, or
// carrying its neighbours' pressure; below it, a free surface's.
constexpr float kSurface = 0.02f;
// The density constraint's CG stops once its residual is this small beside its right side:
// a percent of the density change the substep asks for, which the next substep, warm-started
// from this one's pressures, corrects.
constexpr float kPressureTolerance = 1e-2f;
// The share of a compression beyond rest undone in one substep: all of it at once kicks the
// particles apart faster than the flow moves.
constexpr float kCorrection = 0.3f;
// The density constraint's velocity changes are smoothed by S = I - kSmoothing L', L' its
// neighbours' Laplacian normalised so that S stays positive semi-definite at 1/2 (docs/model.md,
// "The implicit flow"): the constraint cannot see neighbouring layers closing in step, and
// without S it hands half of gravity to such pairing; a lattice at rest then never settles.
constexpr float kSmoothing = 0.5f;

V of(const V3f& v) {
  return {v.x, v.y, v.z};
}
V3f stored(const V& v) {
  return {v.x, v.y, v.z};
}
// A vector's x, y and z in the lanes of one register, with the same IEEE operations lane by
// lane as V's (add, subtract, multiply, tiny): the products over the pairs take one
// instruction for three. On x86-64 an SSE2 register, whose loads read 16 bytes (the fourth
// lane is the next float in memory, never stored: the arrays so read end with a spare V3f);
// elsewhere three floats.
#if defined(__SSE2__)
struct X3 {
  __m128 v;
};
inline X3 load(const V3f& a) {
  return {_mm_loadu_ps(&a.x)};
}
inline X3 splat(float s) {
  return {_mm_set1_ps(s)};
}
inline X3 operator+(X3 a, X3 b) {
  return {_mm_add_ps(a.v, b.v)};
}
inline X3 operator-(X3 a, X3 b) {
  return {_mm_sub_ps(a.v, b.v)};
}
inline X3 operator*(X3 a, X3 b) {
  return {_mm_mul_ps(a.v, b.v)};
}
inline X3 tiny(X3 a) {  // |a| < kTinyTerm: +0, as the scalar tiny's 0.0f
  const __m128 magnitude = _mm_and_ps(a.v, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)));
  return {_mm_andnot_ps(_mm_cmplt_ps(magnitude, _mm_set1_ps(kTinyTerm)), a.v)};
}
inline V3f stored(X3 a) {
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, a.v);
  return {lanes[0], lanes[1], lanes[2]};
}
inline float sum3(X3 a) {  // (x + y) + z: V's dot product of a lane-wise product
  const __m128 xy = _mm_add_ss(a.v, _mm_shuffle_ps(a.v, a.v, 1));
  return _mm_cvtss_f32(_mm_add_ss(xy, _mm_shuffle_ps(a.v, a.v, 2)));
}
#else
struct X3 {
  float x, y, z;
};
inline X3 load(const V3f& a) {
  return {a.x, a.y, a.z};
}
inline X3 splat(float s) {
  return {s, s, s};
}
inline X3 operator+(X3 a, X3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline X3 operator-(X3 a, X3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline X3 operator*(X3 a, X3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
inline X3 tiny(X3 a) {
  return {tiny(a.x), tiny(a.y), tiny(a.z)};
}
inline V3f stored(X3 a) {
  return {a.x, a.y, a.z};
}
inline float sum3(X3 a) {
  return (a.x + a.y) + a.z;
}
#endif

V tiny(const V& v) {
  return {tiny(v.x), tiny(v.y), tiny(v.z)};
}
// Component by component.
V times(const V& a, const V& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}

// In place: s[0] becomes the sum of s[0..kBlock) by halving, as a workgroup's shared memory.
float halving(float* s) {
  for (uint32_t stride = kBlock / 2; stride > 0; stride >>= 1)
    for (uint32_t t = 0; t < stride; ++t) s[t] = s[t] + s[t + stride];
  return s[0];
}

// A cell's place on the Z-order curve (its coordinates' low 10 bits interleaved): cells near
// each other are mostly near on it.
uint32_t zOrder(const Cell& c) {
  const auto spread = [](uint32_t v) {
    v &= 1023u;
    v = (v | (v << 16)) & 0x030000FFu;
    v = (v | (v << 8)) & 0x0300F00Fu;
    v = (v | (v << 4)) & 0x030C30C3u;
    return (v | (v << 2)) & 0x09249249u;
  };
  return spread(uint32_t(c.x)) | (spread(uint32_t(c.y)) << 1) | (spread(uint32_t(c.z)) << 2);
}

// A solid near a particle: its distance (0 inside), its outward normal, its friction.
struct Wall {
  float d;
  V n;
  float friction;
};

// The solids near a particle: each one (its images for the viscosity), their density share
// and its gradient. They fill 1 - prod (1 - phi_b) of the missing density: each solid's
// half-space, their overlaps (edges, corners) once; open = prod (1 - phi_b), slope its
// gradient; own, the particle's own images' t^2, each times 2 - 2 friction.
struct Solids {
  Wall near[kMaxColliders + 1];
  uint32_t count = 0;
  float open = 1.0f, own = 0.0f;
  V slope{0.0f, 0.0f, 0.0f};

  // A solid at distance d, u = 1 - d/radius, outward normal n.
  void add(const ImplicitConstants& ik, float invRadius2, float d, float u, const V& n,
           float friction) {
    const float u4 = (u * u) * (u * u);
    const float phi = ik.phi * ((u4 * u) * (3.0f - 2.0f * u));
    const float dphi = ik.slope * (u4 * (5.0f - 4.0f * u));
    slope = (1.0f - phi) * slope - (open * dphi) * n;
    open = open * (1.0f - phi);
    const float t = 1.0f - ((4.0f * d) * d) * invRadius2;
    if (t > kPairCut) own = own + (2.0f - 2.0f * friction) * (t * t);
    near[count++] = {d, n, 2.0f * friction - 1.0f};
  }
};

// Whether any of the first `count` solids lies closer than `within`.
bool anyCloser(const Wall* near, uint32_t count, float within) {
  for (uint32_t b = 0; b < count; ++b)
    if (near[b].d < within) return true;
  return false;
}

// A pair's viscous weights with j mirrored in each solid near i (across the plane through
// i's nearest point of it, when j lies outside that plane): t^2 plus each image's t^2 on i's
// diagonal, times (2 friction - 1) on its coupling to j. d = x_i - x_j.
void mirrored(const Wall* near, uint32_t walls, const V& d, float invRadius2, float t2,
              float& diagonal, float& coupling) {
  diagonal = coupling = t2;
  for (uint32_t b = 0; b < walls; ++b) {
    const float dj = near[b].d - dot(d, near[b].n);
    if (!(dj > 0.0f)) continue;
    const V mirror = d + (2.0f * dj) * near[b].n;
    const float tm = 1.0f - dot(mirror, mirror) * invRadius2;
    if (!(tm > kPairCut)) continue;
    diagonal = diagonal + tm * tm;
    coupling = coupling + near[b].friction * (tm * tm);
  }
}

// The rest spacing of the lightest flow emitter (m): the closest.
double closestSpacing(const Scene& scene) {
  double spacing = std::cbrt(restVolume(scene));
  for (const Emitter& e : scene.emitters)
    if (e.flow) spacing = std::min(spacing, std::cbrt(double(e.mass) / scene.flow->density));
  return spacing;
}

// Twice the neighbours of a particle on the rest lattice of the lightest flow emitter (the
// closest spacing), within [kLeastNeighbourCap, kMostNeighbourCap]: a list cut short reads a
// dense bulk as sparse and its pairs one-sided.
uint32_t neighbourCap(const Scene& scene) {
  uint64_t neighbours = 0;
  forLattice(closestSpacing(scene), scene.flow->radius, [&](int, int, int, double r) {
    if (r > 0.0) ++neighbours;
  });
  return uint32_t(std::clamp<uint64_t>(2 * neighbours, kLeastNeighbourCap, kMostNeighbourCap));
}

// Twice the lattice sites of the lightest flow emitter in a grid cell (a cube a radius wide),
// at least flow.comp's kFlowBucketCap: at a radius of 4 spacings and more a cell holds 64 at
// rest, and a bulk read to 64 a bucket reads as sparse.
uint32_t bucketCap(const Scene& scene) {
  const double sites = std::pow(double(scene.flow->radius) / closestSpacing(scene), 3.0);
  return std::max(gpu::kFlowBucketCap, uint32_t(std::ceil(2.0 * sites)));
}

}  // namespace

ImplicitConstants implicitConstants(const Scene& scene) {
  const Flow& f = *scene.flow;
  const double radius = f.radius, v0 = restVolume(scene);
  const double s0 = std::cbrt(v0), lattice = latticeSum(s0, radius);
  ImplicitConstants k{};
  // A solid's density: the half-space beyond it filled at rest, sum (1 - r/radius)^3 / S over
  // it as an integral, 2 pi radius^3 / (S V0) U^5 (3 - 2U) / 60 at U = 1 - d/radius; scaled so
  // that a particle half a spacing above a solid on the rest lattice has theta = 1.
  double upper = 0.0, gradients = 0.0, degree = 0.0;
  forLattice(s0, radius, [&](int, int, int c, double r) {
    const double u = 1.0 - r / radius, t = 1.0 - (r * r) / (radius * radius);
    if (c >= 0) upper += u * u * u;
    if (r > 0.0) gradients += std::pow(3.0 / (lattice * radius) * u * u, 2);
    if (r > 0.0) degree += t * t;
  });
  const double half = 1.0 - 0.5 * s0 / radius;
  const double continuum = 2.0 * kPi * radius * radius * radius / (lattice * v0);
  const double scale =
      (1.0 - upper / lattice) / (continuum * std::pow(half, 5) * (3.0 - 2.0 * half) / 60.0);
  k.phi = float(scale * continuum / 60.0);
  k.slope = float(-scale * continuum / (20.0 * radius));
  k.epsilon = float(kRelax * gradients);
  k.restDegree = float(degree);
  k.tolerance2 = kTolerance * kTolerance;
  k.pressureTolerance2 = kPressureTolerance * kPressureTolerance;
  k.near = float(s0);
  k.coolAir = f.coolingAir;
  k.coolContact = float(double(f.coolingAir) + f.coolingGround);
  k.invStep = float(1.0 / double(scene.h()));
  for (uint32_t n = 1; n <= kMaxSubsteps; ++n) {
    k.cfl2[n - 1] = float(std::pow(double(n) * kCourant * s0, 2));
    k.inverse[n - 1] = float(1.0 / double(n));
  }
  k.cap = neighbourCap(scene);
  k.bucketCap = bucketCap(scene);
  return k;
}

namespace {

// The sums over flow indices f < n of each of term(f)'s K values, in their order as the GPU
// takes it: each block of kBlock indices by halving; then invocation t of one workgroup adds
// the blocks t, t + kBlock, ... in order, and those kBlock sums are halved. Each value's sum
// has the bits of its sum alone. On the calling thread: a barrier costs more than the sum,
// and far more where the threads share their cores with other work.
template <unsigned K, class Term>
std::array<float, K> inOrder(size_t n, const Term& term) {
  using Values = std::array<float, K>;
  const size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<Values> partial(blocks);
  for (size_t b = 0; b < blocks; ++b) {
    float s[K][kBlock];
    for (uint32_t t = 0; t < kBlock; ++t) {
      const size_t f = b * kBlock + t;
      const Values v = f < n ? term(f) : Values{};
      for (unsigned k = 0; k < K; ++k) s[k][t] = v[k];
    }
    for (unsigned k = 0; k < K; ++k) partial[b][k] = halving(s[k]);
  }
  Values sums;
  for (unsigned k = 0; k < K; ++k) {
    float s[kBlock];
    for (uint32_t t = 0; t < kBlock; ++t) {
      float sum = 0.0f;
      for (size_t c = t; c < blocks; c += kBlock) sum = sum + partial[c][k];
      s[t] = sum;
    }
    sums[k] = halving(s);
  }
  return sums;
}

}  // namespace

// The sums of each of term(place)'s K values over the flow indices, in order (inOrder).
template <unsigned K, class Term>
std::array<float, K> FlowStepper::orderedSums(const Term& term) const {
  return inOrder<K>(place_.size(), [&](size_t f) { return term(place_[f]); });
}

// The sums of the first K values of the terms a pass left per flow index (terms_).
template <unsigned K>
std::array<float, K> FlowStepper::termSums() const {
  return inOrder<K>(place_.size(), [&](size_t f) {
    const V3f& t = terms_[f];
    const float all[3] = {t.x, t.y, t.z};
    std::array<float, K> v;
    for (unsigned k = 0; k < K; ++k) v[k] = all[k];
    return v;
  });
}

void FlowStepper::implicitStep(State& state) {
  killNonFinite(state);
  float fastest = 0.0f;  // the largest squared speed of a flow particle that may move
  for (uint32_t i : flowSlots_) {
    const Particle& p = state.particles[i];
    if (!(p.age < 0.0f) && state.crust[i] == 0)
      fastest = std::max(fastest, (p.vx * p.vx + p.vy * p.vy) + p.vz * p.vz);
  }
  const float h = reference_.scene().h();
  const float h2 = h * h;
  uint32_t n = 1;
  while (n < kMaxSubsteps && !(h2 * fastest <= ik_.cfl2[n - 1])) ++n;
  for (uint32_t k = 0; k < n; ++k) substep(state, ik_.inverse[n - 1], n);
}

void FlowStepper::substep(State& state, float fraction, uint32_t substeps) {
  const float hs = reference_.scene().h() * fraction;
  sort(state);
  arrange();
  for (size_t f = 0; f < flowSlots_.size(); ++f) {
    const uint32_t i = at_[f];
    Own& o = own_[f];
    o.liquid = !(state.particles[i].age < 0.0f) && state.crust[i] == 0 &&
               state.temperature[i] > k_.solidus;
    o.nu = flowViscosity(k_, state.temperature[i]);
  }
  gatherNeighbours(state, hs);
  forces(state, fraction);
  const float invHs = ik_.invStep * float(substeps);
  // The density constraint before the viscosity: the viscosity then damps, in the same
  // substep, what the constraint cannot see (neighbouring layers closing in step).
  solveDensity(state, hs, invHs);
  viscousSystem(hs);
  solveViscosity();
  move(state, hs, fraction, invHs);
}

// Where the substep keeps each particle's values: the alive ones along the Z-order curve of
// their cells (then by slot), the unborn after them by slot, so that a particle's neighbours'
// values lie near each other in memory. Sums still run over flow indices in order.
void FlowStepper::arrange() {
  keys_.resize(sorted_.size());
  for (size_t e = 0; e < sorted_.size(); ++e)
    keys_[e] = (uint64_t(zOrder(cells_[sorted_[e]])) << 32) | sorted_[e];
  std::sort(keys_.begin(), keys_.end());
  for (const uint32_t i : flowSlots_) indexOf_[i] = kNotFlow;
  uint32_t place = 0;
  for (const uint64_t key : keys_) {
    at_[place] = uint32_t(key);
    indexOf_[uint32_t(key)] = place++;
  }
  for (const uint32_t i : flowSlots_)
    if (indexOf_[i] == kNotFlow) {  // unborn
      at_[place] = i;
      indexOf_[i] = place++;
    }
  for (size_t f = 0; f < flowSlots_.size(); ++f) {
    place_[f] = indexOf_[flowSlots_[f]];
    indexAt_[place_[f]] = uint32_t(f);
  }
}

// Calls visit(d, u, n, friction) for the ground and each collider within the radius of x: d
// its distance (0 inside), u = 1 - d/radius, n its outward normal. A collider is taken as the
// plane of its nearest face.
template <class Visit>
void FlowStepper::walls(float x, float y, float z, const Visit& visit) const {
  const Scene& s = reference_.scene();
  const V at{x, y, z};
  const auto offer = [&](float d, const V& n, float friction) {
    const float clamped = std::max(d, 0.0f);
    const float u = 1.0f - clamped * k_.invRadius;
    if (u > 0.0f) visit(clamped, u, n, friction);
  };
  offer(y, V{0.0f, 1.0f, 0.0f}, s.friction);
  for (size_t c = 0; c < s.colliders.size(); ++c) {
    const Collider& col = s.colliders[c];
    const V d = at - Model::of(col.position);
    switch (col.type) {
      case ColliderType::Plane: {
        const V n = Model::of(reference_.planeNormal(c));
        offer(dot(d, n), n, col.friction);
        break;
      }
      case ColliderType::Sphere: {
        const float q = dot(d, d);
        if (!(q >= gpu::kAxisSquared)) {
          offer(-col.radius, V{0.0f, 1.0f, 0.0f}, col.friction);
          break;
        }
        const float inv = Model::inverseRoot(q);
        offer(q * inv - col.radius, inv * d, col.friction);
        break;
      }
      case ColliderType::Box: {
        const Vec3& e = col.size;
        const bool standing = col.position.y <= e.y;  // its bottom face is the ground's
        const float gx = std::fabs(d.x) - e.x, gz = std::fabs(d.z) - e.z;
        const float gy = standing ? d.y - e.y : std::fabs(d.y) - e.y;
        if (gx >= gy && gx >= gz)
          offer(gx, V{d.x >= 0.0f ? 1.0f : -1.0f, 0.0f, 0.0f}, col.friction);
        else if (gy >= gz)
          offer(gy, V{0.0f, standing || d.y >= 0.0f ? 1.0f : -1.0f, 0.0f}, col.friction);
        else
          offer(gz, V{0.0f, 0.0f, d.z >= 0.0f ? 1.0f : -1.0f}, col.friction);
        break;
      }
      case ColliderType::Cone: {
        const ConeConstants& k = reference_.cone(c);
        const float ry = col.baseRadius + k.slope * d.y;
        const float q = d.x * d.x + d.z * d.z;
        const bool offAxis = q >= gpu::kAxisSquared;  // on the axis: the radial direction is +x
        const float inv = offAxis ? Model::inverseRoot(q) : 0.0f;
        const float rx = offAxis ? d.x * inv : 1.0f, rz = offAxis ? d.z * inv : 0.0f;
        const float rho = offAxis ? q * inv : 0.0f;
        const float side = (rho - ry) * k.radial, top = d.y - col.height;
        if (top > side)
          offer(top, V{0.0f, 1.0f, 0.0f}, col.friction);
        else
          offer(side, V{k.radial * rx, k.vertical, k.radial * rz}, col.friction);
        break;
      }
    }
  }
}

// Each alive particle's neighbours (at most ik_.cap, in the grid's order), its density
// ratio with the solids' share, its constraint's gradients, the solids' viscous weight, the
// conduction's stability, and whether it touches crust or a solid.
void FlowStepper::gatherNeighbours(const State& state, float hs) {
  const float conduction = hs * k_.conduction;
  ranges(sorted_.size(), [&](size_t begin, size_t end) {
    // Places run along the Z-order curve of the cells, so a cell's particles come one after
    // another: the chunk keeps the candidates of the cell it searched last.
    Candidates near;
    Found pairs;
    size_t next = begin * ik_.cap;
    for (size_t e = begin; e < end; ++e) {
      const uint32_t i = at_[e];  // the alive particles come first
      if (!near.filled || !(near.cell == cells_[i])) candidates(cells_[i], near);
      found(state, i, near, pairs);
      first_[e] = next;
      gatherPairs(state, uint32_t(e), pairs, hs, conduction);
      next += count_[e];
    }
  });
  for (size_t f = sorted_.size(); f < flowSlots_.size(); ++f) {  // the unborn: no pairs
    first_[f] = 0;
    count_[f] = 0;
  }
}

// Place f's pairs (found()) into its links, slopes and kernels, and its own sums: the first
// ik_.cap of them besides f itself.
void FlowStepper::gatherPairs(const State& state, uint32_t f, const Found& pairs, float hs,
                              float conduction) {
  const uint32_t i = at_[f];
  const Particle& p = state.particles[i];
  Own& o = own_[f];
  Solids solids;
  this->walls(p.px, p.py, p.pz, [&](float d, float u, const V& n, float friction) {
    solids.add(ik_, k_.invRadius2, d, u, n, friction);
  });
  Link* links = linksOf(f);
  Slope* slopes = slopesOf(f);
  Kernel* kernels = kernelsOf(f);
  uint32_t count = 0;
  float theta = 0.0f, moving = 0.0f, conductive = 0.0f;
  V grad{0.0f, 0.0f, 0.0f};
  bool touches = false;
  for (uint32_t m = 0; m < pairs.count; ++m) {
    const uint32_t j = pairs.slot[m];
    if (j != i && count == ik_.cap) continue;
    const FlowWeights& w = weights_[emitterOfSlot_[j]];
    const V n{pairs.nx[m], pairs.ny[m], pairs.nz[m]};
    const float tr = std::max(1.0f - pairs.r[m] * k_.invRadius, 0.0f);
    theta = theta + w.density * ((tr * tr) * tr);
    if (j == i) continue;
    const uint32_t g = indexOf_[j];
    const V unit = (tr * tr) * n;  // the constraint's gradient towards j is -pressure unit
    const V push = w.pressure * unit;
    grad = grad - push;
    if (own_[g].liquid) moving = moving + dot(push, push);
    const float t2 = pairs.t[m] * pairs.t[m];
    float diagonal, coupling;
    mirrored(solids.near, solids.count, V{pairs.dx[m], pairs.dy[m], pairs.dz[m]}, k_.invRadius2,
             t2, diagonal, coupling);
    conductive = conductive + tiny(w.viscous * t2);
    touches = touches || (state.crust[j] != 0 && pairs.q[m] < k_.touch2);
    links[count] = {g, 0.0f};
    slopes[count] = {stored(unit), w.pressure};
    kernels[count++] = {t2, diagonal, coupling};
  }
  theta = theta + (1.0f - solids.open);
  grad = grad - solids.slope;  // the solids' share of the gradient is -slope
  const bool close = anyCloser(solids.near, solids.count, ik_.near);
  count_[f] = count;
  o.theta = theta;
  o.invG = reciprocal(hs * ((dot(grad, grad) + moving) + ik_.epsilon));
  o.wallViscous = solids.own;
  o.conductive = stable(conduction * conductive);
  o.touches = touches || close;
  o.near = close;
  gradWall_[f] = stored(V{-solids.slope.x, -solids.slope.y, -solids.slope.z});
}

// The velocities after the viscosity: per liquid particle i,
//   (m_i + sum_j a_ij + wall_i) v_i - sum_{liquid j} a_ij v_j = m_i v*_i + sum_{solid j} a_ij v_j
// with m the volume in V0, a_ij = hs m_i viscous_j (nu_i + nu_j) t^2, wall_i =
// 2 hs m_i nu_i wallViscous_i, v* the velocity after the forces and the density constraint;
// solved by CG from v*, each component on its own.
float FlowStepper::viscousCoefficient(uint32_t f, uint32_t j, float hs) const {
  const float hsm = hs * weights_[emitterOfSlot_[at_[f]]].volume;
  return (hsm * weights_[emitterOfSlot_[at_[j]]].viscous) * (own_[f].nu + own_[j].nu);
}

// v: each liquid particle's start-of-substep velocity after the forces, flushed; the others'
// start-of-substep velocity.
void FlowStepper::forces(const State& state, float fraction) {
  const Scene& s = reference_.scene();
  parallel(flowSlots_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e), i = at_[f];
    const Particle& p = state.particles[i];
    const V v0{p.vx, p.vy, p.vz};
    if (!own_[f].liquid) {
      v_[f] = stored(v0);
      return;
    }
    const EmitterConstants& ek = reference_.constants(emitterOfSlot_[i]);
    v_[f] = stored(Model::flushed(
        v0 + (ek.hm * fraction) * Model::force<Modules::Any>(s, V{p.px, p.py, p.pz}, v0, ek.w)));
  });
}

// The viscosity's system: each liquid row's diagonal, right side b, and the CG's start from
// v* (its residual r, z = r / D, direction p = z). A solid's v is its start velocity.
void FlowStepper::viscousSystem(float hs) {
  parallel(flowSlots_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e), i = at_[f];
    Own& o = own_[f];
    p_[f] = V3f{0.0f, 0.0f, 0.0f};  // a solid's direction stays 0: its pairs' products are 0
    if (!o.liquid) return;
    const size_t emitter = emitterOfSlot_[i];
    const float m = weights_[emitter].volume;
    const V vstar = of(v_[f]);
    float sum = 0.0f;
    V fixed{0.0f, 0.0f, 0.0f}, pull{0.0f, 0.0f, 0.0f};
    Link* links = linksOf(f);
    const Kernel* kernels = kernelsOf(f);
    for (uint32_t k = 0; k < count_[f]; ++k) {
      const float a = viscousCoefficient(f, links[k].j, hs);
      sum = sum + a * kernels[k].diagonal;
      const float coupling = a * kernels[k].coupling;
      const V term = tiny(coupling * of(v_[links[k].j]));
      // A solid neighbour's share is on the right side: 0 in the product (pull never -0).
      const bool liquid = own_[links[k].j].liquid;
      links[k].weight = liquid ? coupling : 0.0f;
      if (liquid)
        pull = pull + term;
      else
        fixed = fixed + term;
    }
    o.diag = (m + sum) + (((hs * m) * weights_[emitter].viscous) * (o.nu + o.nu)) * o.wallViscous;
    o.invDiag = reciprocal(o.diag);
    const V b = m * vstar + fixed;
    const V r = b - (o.diag * vstar - pull);
    b_[f] = stored(b);
    r_[f] = stored(r);
    z_[f] = stored(tiny(o.invDiag * r));
    p_[f] = z_[f];
  });
}

// The viscosity's product q = A p on the liquid particles, and p.q's terms (terms_).
void FlowStepper::multiplyViscous() {
  parallel(flowSlots_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e);
    const Own& o = own_[f];
    if (!o.liquid) {
      terms_[indexAt_[f]] = V3f{0.0f, 0.0f, 0.0f};
      return;
    }
    X3 pull = splat(0.0f);
    const Link* links = linksOf(f);
    for (uint32_t c = 0; c < count_[f]; ++c)
      pull = pull + tiny(splat(links[c].weight) * load(p_[links[c].j]));
    const X3 p = load(p_[f]), q = tiny(splat(o.diag) * p) - pull;
    q_[f] = stored(q);
    terms_[indexAt_[f]] = stored(tiny(p * q));
  });
}

// The viscosity's CG, each component with its own alpha and beta, until its r.z is below
// tolerance2 b.(b / D) or kViscousIterations.
void FlowStepper::solveViscosity() {
  const size_t n = flowSlots_.size();
  // The three components' sums of a liquid particle's term, in one pass.
  const auto sums = [&](auto term) {
    const std::array<float, 3> s = orderedSums<3>([&](size_t f) {
      const V v = own_[f].liquid ? tiny(term(f)) : V{0, 0, 0};
      return std::array<float, 3>{v.x, v.y, v.z};
    });
    return V{s[0], s[1], s[2]};
  };
  const auto left = [&] {  // the same sums of the terms the pass before left
    const std::array<float, 3> s = termSums<3>();
    return V{s[0], s[1], s[2]};
  };
  V rz = sums([&](size_t f) { return times(of(r_[f]), of(z_[f])); });
  const V bb = sums([&](size_t f) { return times(of(b_[f]), own_[f].invDiag * of(b_[f])); });
  const V limit = ik_.tolerance2 * bb;
  bool active[3] = {rz.x > limit.x, rz.y > limit.y, rz.z > limit.z};
  for (uint32_t k = 0; k < kViscousIterations && (active[0] || active[1] || active[2]); ++k) {
    multiplyViscous();
    const V pq = left();
    float alpha[3], beta[3];
    const float rzs[3] = {rz.x, rz.y, rz.z}, pqs[3] = {pq.x, pq.y, pq.z};
    for (int c = 0; c < 3; ++c) {
      active[c] = active[c] && pqs[c] > 0.0f;
      alpha[c] = active[c] ? rzs[c] * reciprocal(pqs[c]) : 0.0f;
    }
    const V a{alpha[0], alpha[1], alpha[2]};
    parallel(n, [&](size_t e) {  // and r.z's terms
      const uint32_t f = uint32_t(e);
      if (!own_[f].liquid) {
        terms_[indexAt_[f]] = V3f{0.0f, 0.0f, 0.0f};
        return;
      }
      v_[f] = stored(of(v_[f]) + tiny(times(a, of(p_[f]))));
      const V r = of(r_[f]) - tiny(times(a, of(q_[f]))), z = tiny(own_[f].invDiag * r);
      r_[f] = stored(r);
      z_[f] = stored(z);
      terms_[indexAt_[f]] = stored(tiny(times(r, z)));
    });
    const V next = left();
    const float nexts[3] = {next.x, next.y, next.z}, limits[3] = {limit.x, limit.y, limit.z};
    float kept[3];
    for (int c = 0; c < 3; ++c) {
      beta[c] = active[c] ? nexts[c] * reciprocal(rzs[c]) : 0.0f;
      kept[c] = active[c] ? nexts[c] : rzs[c];
      active[c] = active[c] && nexts[c] > limits[c];
    }
    rz = V{kept[0], kept[1], kept[2]};
    const V bt{beta[0], beta[1], beta[2]};
    parallel(n, [&](size_t e) {
      const uint32_t f = uint32_t(e);
      if (own_[f].liquid) p_[f] = stored(of(z_[f]) + tiny(times(bt, of(p_[f]))));
    });
  }
}

float FlowStepper::pressureOf(uint32_t f) const {
  return weights_[emitterOfSlot_[at_[f]]].pressure;
}

// d theta_f / dt of velocities u: sum_j -pressure_j e_fj . (u_f - u_j) + gradWall . u_f, for
// each lane's u in one pass over f's pairs; each lane's sum in the order of one alone.
template <unsigned N>
std::array<float, N> FlowStepper::rateOf(uint32_t f,
                                         const std::array<const std::vector<V3f>*, N>& u) const {
  X3 uf[N];
  std::array<float, N> rate{};
  for (unsigned k = 0; k < N; ++k) uf[k] = load((*u[k])[f]);
  const Link* links = linksOf(f);
  const Slope* slopes = slopesOf(f);
  for (uint32_t c = 0; c < count_[f]; ++c) {
    const X3 e = load(slopes[c].e);  // e's 16 bytes: e, then pressure
    const float pressure = slopes[c].pressure;
    for (unsigned k = 0; k < N; ++k)
      rate[k] = rate[k] - tiny(pressure * sum3(e * (uf[k] - load((*u[k])[links[c].j]))));
  }
  for (unsigned k = 0; k < N; ++k) rate[k] = rate[k] + tiny(sum3(load(gradWall_[f]) * uf[k]));
  return rate;
}

// u = -J^T m, the velocity change of liquid f from the multipliers m (0 outside the active
// set): sum_j (m_f pressure_j + m_j pressure_f) e_fj - m_f gradWall_f; then w = S u.
template <unsigned N>
void FlowStepper::correction(const Multipliers<N>& m, const Lanes<N>& lane) {
  parallel(flowSlots_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e);
    if (!own_[f].liquid) return;
    const float mine = pressureOf(f);
    X3 dv[N];
    for (unsigned k = 0; k < N; ++k) dv[k] = splat(0.0f);
    const Link* links = linksOf(f);
    const Slope* slopes = slopesOf(f);
    for (uint32_t c = 0; c < count_[f]; ++c)
      for (unsigned k = 0; k < N; ++k)
        dv[k] = dv[k] + tiny(splat((*m[k])[f] * slopes[c].pressure + (*m[k])[links[c].j] * mine) *
                             load(slopes[c].e));  // e's 16 bytes: e, then pressure
    for (unsigned k = 0; k < N; ++k)
      u_[lane[k]][f] = stored(dv[k] - tiny(splat((*m[k])[f]) * load(gradWall_[f])));
  });
  smooth<N>(lane);
}

// w = S u = u - kSmoothing sum_j weight_fj (u_f - u_j) on the liquid particles, 0 on the
// others, weight_fj = t^2 min(1/d_f, 1/d_j) (0 for a solid j): symmetric, and by Gershgorin's
// bound positive semi-definite, so that J S J^T stays a CG's matrix; the pairs cancel, so
// momentum is kept.
template <unsigned N>
void FlowStepper::smooth(const Lanes<N>& lane) {
  parallel(flowSlots_.size(), [&](size_t f) {
    if (!own_[f].liquid) {
      for (unsigned k = 0; k < N; ++k) w_[lane[k]][f] = V3f{0.0f, 0.0f, 0.0f};
      return;
    }
    X3 uf[N], sum[N];
    for (unsigned k = 0; k < N; ++k) {
      uf[k] = load(u_[lane[k]][f]);
      sum[k] = splat(0.0f);
    }
    const Link* links = linksOf(f);
    for (uint32_t c = 0; c < count_[f]; ++c)
      for (unsigned k = 0; k < N; ++k)
        sum[k] = sum[k] + tiny(splat(links[c].weight) * (uf[k] - load(u_[lane[k]][links[c].j])));
    for (unsigned k = 0; k < N; ++k)
      w_[lane[k]][f] = stored(uf[k] - tiny(splat(kSmoothing) * sum[k]));
  });
}

// The density constraint on the velocities (docs/model.md, "The implicit flow"): for the
// active liquid particles (compressing under the forces, or pressed at the last substep),
// multipliers m with (J S J^T + epsilon) m = C / hs, C = theta - 1 + hs J v the predicted
// density error; solved by CG from the last substep's pressures, then m >= 0 kept and the
// velocities moved by -S J^T m.
// q = (J S J^T + epsilon) x on the active set: u = -J^T x, w = S u, then q = -J w + epsilon x.
template <unsigned N>
void FlowStepper::multiplyDensity(const Multipliers<N>& x, const Lanes<N>& lane) {
  correction<N>(x, lane);
  std::array<const std::vector<V3f>*, N> w;
  for (unsigned k = 0; k < N; ++k) w[k] = &w_[lane[k]];
  parallel(flowSlots_.size(), [&](size_t f) {  // and x.q's terms, each lane's in its place
    const bool active = own_[f].active;
    const std::array<float, N> rate =
        active ? rateOf<N>(uint32_t(f), w) : std::array<float, N>{};
    float term[2] = {0.0f, 0.0f};
    for (unsigned k = 0; k < N; ++k) {
      aq_[lane[k]][f] = active ? tiny(ik_.epsilon * (*x[k])[f]) - rate[k] : 0.0f;
      term[lane[k]] = tiny((*x[k])[f] * aq_[lane[k]][f]);
    }
    terms_[indexAt_[f]] = V3f{term[0], term[1], 0.0f};
  });
}

// S's weights: each liquid particle's 1/d, then each pair's t^2 min(1/d_f, 1/d_j).
void FlowStepper::smoothingWeights() {
  parallel(flowSlots_.size(), [&](size_t f) {
    float degree = 0.0f;
    const Link* links = linksOf(f);
    const Kernel* kernels = kernelsOf(f);
    for (uint32_t c = 0; c < count_[f]; ++c)
      if (own_[links[c].j].liquid) degree = degree + kernels[c].t2;
    own_[f].invDegree = reciprocal(std::max(degree, ik_.restDegree));
  });
  parallel(flowSlots_.size(), [&](size_t f) {
    Link* links = linksOf(f);
    const Kernel* kernels = kernelsOf(f);
    for (uint32_t c = 0; c < count_[f]; ++c) {
      const Own& j = own_[links[c].j];
      links[c].weight = j.liquid ? kernels[c].t2 * std::min(own_[f].invDegree, j.invDegree) : 0.0f;
    }
  });
}

// The density constraint's active set, right sides and start: the last substep's pressures.
// The right side is the velocities' share (the predicted compression rate) plus the
// positions' (the compression beyond rest to undo, rhsP_).
void FlowStepper::densitySystem(const State& state, float hs, float invHs) {
  smoothingWeights();
  parallel(flowSlots_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e);
    Own& o = own_[f];
    u_[0][f] = u_[1][f] = V3f{0.0f, 0.0f, 0.0f};
    if (!o.liquid) {  // its multiplier is read by its liquid neighbours' push: none
      o.active = 0;
      lambda_[f] = lambdaP_[f] = rhsP_[f] = 0.0f;
      return;
    }
    const float warm = state.pressure[at_[f]];
    // Compression beyond rest is undone in the substep; a sparser bulk is not pulled in.
    const float undo = kCorrection * std::max(o.theta - 1.0f, 0.0f);
    rhs_[f] = (undo + hs * rateOf<1>(f, {&v_})[0]) * invHs;
    rhsP_[f] = undo * invHs;
    o.active = o.theta > 1.0f - kSurface || warm > 0.0f;
    lambda_[f] = o.active ? warm * hs : 0.0f;
    lambdaP_[f] = 0.0f;
  });
}

// Both of the constraint's systems, (J S J^T + epsilon) x = b on the active set: lambda_ for
// rhs_ from the last substep's pressures (lane 0), lambdaP_ for rhsP_ from 0 (lane 1). Each
// is a Jacobi-preconditioned CG until its r.z <= limit or kPressureIterations; they run side
// by side, their products in one pass over the pairs while both run, each lane's bits those
// of its CG alone.
void FlowStepper::solveConstraints(float hs, float limit) {
  const size_t n = flowSlots_.size();
  std::vector<float>* x[2] = {&lambda_, &lambdaP_};
  multiplyDensity<1>({&lambda_}, {0});
  parallel(n, [&](size_t f) {
    const Own& o = own_[f];
    const float r[2] = {rhs_[f] - aq_[0][f], rhsP_[f]};
    for (unsigned k = 0; k < 2; ++k) {
      ar_[k][f] = o.active ? r[k] : 0.0f;
      az_[k][f] = o.active ? tiny((o.invG * hs) * ar_[k][f]) : 0.0f;
      ap_[k][f] = az_[k][f];
    }
  });
  const std::array<float, 2> first = orderedSums<2>([&](size_t f) {
    return std::array<float, 2>{tiny(ar_[0][f] * az_[0][f]), tiny(ar_[1][f] * az_[1][f])};
  });
  float rz[2] = {first[0], first[1]};
  bool active[2] = {rz[0] > limit, rz[1] > limit};
  for (uint32_t it = 0; it < kPressureIterations && (active[0] || active[1]); ++it) {
    if (active[0] && active[1])
      multiplyDensity<2>({&ap_[0], &ap_[1]}, {0, 1});
    else if (active[0])
      multiplyDensity<1>({&ap_[0]}, {0});
    else
      multiplyDensity<1>({&ap_[1]}, {1});
    float alpha[2] = {0.0f, 0.0f};
    const std::array<float, 2> pq = termSums<2>();
    for (unsigned k = 0; k < 2; ++k) {
      if (!active[k]) continue;
      active[k] = pq[k] > 0.0f;
      if (active[k]) alpha[k] = rz[k] * reciprocal(pq[k]);
    }
    parallel(n, [&](size_t f) {  // and r.z's terms
      float term[2] = {0.0f, 0.0f};
      for (unsigned k = 0; k < 2 && own_[f].active; ++k) {
        if (!active[k]) continue;
        (*x[k])[f] = (*x[k])[f] + tiny(alpha[k] * ap_[k][f]);
        ar_[k][f] = ar_[k][f] - tiny(alpha[k] * aq_[k][f]);
        az_[k][f] = tiny((own_[f].invG * hs) * ar_[k][f]);
        term[k] = tiny(ar_[k][f] * az_[k][f]);
      }
      terms_[indexAt_[f]] = V3f{term[0], term[1], 0.0f};
    });
    float beta[2] = {0.0f, 0.0f};
    const std::array<float, 2> nexts = termSums<2>();
    for (unsigned k = 0; k < 2; ++k) {
      if (!active[k]) continue;
      const float next = nexts[k];
      beta[k] = next * reciprocal(rz[k]);
      rz[k] = next;
      active[k] = next > limit;
    }
    parallel(n, [&](size_t f) {
      if (!own_[f].active) return;
      for (unsigned k = 0; k < 2; ++k)
        if (active[k]) ap_[k][f] = az_[k][f] + tiny(beta[k] * ap_[k][f]);
    });
  }
}

// The multipliers m >= 0 of the whole right side, and of its positions' share p, 0 <= p <= m
// (docs/model.md, "The implicit flow"): the velocities move by -S J^T (m - p); the positions'
// share moves the particles in this substep only (pseudo_), so that undoing a compression
// gives no particle speed.
void FlowStepper::solveDensity(const State& state, float hs, float invHs) {
  const size_t n = flowSlots_.size();
  densitySystem(state, hs, invHs);
  // Both CGs stop at pressureTolerance2 b.(b / D) of the whole right side: the positions'
  // share is as accurate as the whole, however small it is.
  const float bb = orderedSums<1>([&](size_t f) {
    return std::array<float, 1>{own_[f].active ? tiny(rhs_[f] * ((own_[f].invG * hs) * rhs_[f]))
                                               : 0.0f};
  })[0];
  solveConstraints(hs, ik_.pressureTolerance2 * bb);
  parallel(n, [&](size_t f) {
    lambda_[f] = std::max(lambda_[f], 0.0f);
    lambdaP_[f] = std::min(std::max(lambdaP_[f], 0.0f), lambda_[f]);
    own_[f].total = lambda_[f];
    lambda_[f] = lambda_[f] - lambdaP_[f];  // from here, the velocities' share m - p
  });
  correction<2>({&lambdaP_, &lambda_}, {0, 1});
  parallel(n, [&](size_t f) {
    // The positions' share moves a particle at most half a spacing in a substep: more is a
    // particle squeezed into a corner, not an overlap undone.
    V w = own_[f].liquid ? of(w_[0][f]) : V{0.0f, 0.0f, 0.0f};
    const float most = (0.5f * ik_.near) * invHs, q = dot(w, w);
    if (q > most * most) w = (most * Model::inverseRoot(q)) * w;
    pseudo_[f] = stored(w);
    if (own_[f].liquid) v_[f] = stored(of(v_[f]) + of(w_[1][f]));
  });
}

// The heat flow f gains from its neighbours in the substep: the explicit flow's sum over its
// kept neighbours, `conduction` = hs 2 conduction.
float FlowStepper::conducted(const State& state, uint32_t f, float conduction) const {
  const std::vector<float>& temperature = state.temperature;
  const uint32_t i = at_[f];
  float dT = 0.0f;
  const Link* links = linksOf(f);
  const Kernel* kernels = kernelsOf(f);
  for (uint32_t c = 0; c < count_[f]; ++c) {
    const uint32_t j = at_[links[c].j];
    dT = dT + tiny(((weights_[emitterOfSlot_[j]].viscous * conduction) * kernels[c].t2) *
                   std::min(own_[f].conductive, own_[links[c].j].conductive) *
                   (temperature[j] - temperature[i]));
  }
  return dT;
}

// The substep's move: liquid particles with their solved velocities, cinders falling, crust
// kept; then the solids' contact, heat and age, as the explicit flow's step.
void FlowStepper::move(State& state, float hs, float fraction, float invHs) {
  const Scene& s = reference_.scene();
  const float conduction = hs * k_.conduction;
  std::vector<Particle>& particles = state.particles;
  const std::vector<float>& temperature = state.temperature;
  next_.resize(sorted_.size());
  parallel(sorted_.size(), [&](size_t e) {
    const uint32_t f = uint32_t(e), i = at_[f];
    const Own& o = own_[f];
    const size_t emitter = emitterOfSlot_[i];
    const Particle& p = particles[i];
    const bool isCrust = state.crust[i] != 0;
    const float dT = conducted(state, f, conduction);
    const V x0{p.px, p.py, p.pz};
    V x = x0, v{p.vx, p.vy, p.vz};
    bool touched = false, becomesCrust = isCrust, dies = false;
    if (!isCrust) {
      const EmitterConstants& ek = reference_.constants(emitter);
      if (o.liquid) {
        v = Model::flushed(of(v_[f]));
        x = x + hs * (v + of(pseudo_[f]));
      } else if (o.touches) {  // a solid touching crust or a solid: crust where it is
        becomesCrust = true;
      } else {  // a cinder: falls as any particle
        v = Model::flushed(v + (ek.hm * fraction) * Model::force<Modules::Any>(s, x, v, ek.w));
        x = x + hs * v;
      }
      touched = settle(contact_, reference_, x0, o.liquid, x, v, becomesCrust, dies);
    }
    const float cool = hs * (touched || o.near ? ik_.coolContact : ik_.coolAir);
    float age, t1;
    finish(s.emitters[emitter], k_.ambient, hs, cool, p.age, temperature[i], dT, dies, age, t1,
           becomesCrust);
    next_[e] = {{x.x, x.y, x.z, age, v.x, v.y, v.z, p.mass}, t1, uint8_t(becomesCrust ? 1 : 0)};
    // The pressure the next substep starts from: a liquid particle's that stays liquid.
    pressure_[f] = o.liquid && !dies && !(age < 0.0f) ? o.total * invHs : 0.0f;
  });
  for (size_t e = 0; e < sorted_.size(); ++e) {
    const uint32_t i = at_[e];
    particles[i] = next_[e].particle;
    state.temperature[i] = next_[e].temperature;
    state.crust[i] = next_[e].crust;
    state.pressure[i] = pressure_[e];  // place e holds slot i
  }
}

}  // namespace lava::detail
