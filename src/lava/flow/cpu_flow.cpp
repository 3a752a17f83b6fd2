// The flow on the CPU (docs/model.md, "The flow"): the grid, the two neighbour passes and the
// flow particles' step, one particle at a time, in plain float32 built with -ffp-contract=off.
#include "flow.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "flow/lattice.h"
#include "flow/stepper-inl.h"
#include "sim/constants.h"
#include "sim/reference.h"

namespace lava::detail {
namespace {

using namespace flowcpu;

// Cells are clamped to +-2^20 per axis (far particles share the outermost cells).
constexpr float kCellLimit = 1048576.0f;

}  // namespace

FlowConstants flowConstants(const Scene& scene) {
  const Flow& f = *scene.flow;
  const double radius = f.radius, h = scene.h();
  const double spacing = std::cbrt(restVolume(scene));
  const double c = std::min(double(f.soundSpeed), 0.4 * radius / h);
  FlowConstants k{};
  k.invRadius = float(1.0 / radius);
  k.invRadius2 = float(1.0 / (radius * radius));
  k.touch2 = float(1.5625 * spacing * spacing);
  k.pressure = float(c * c);
  k.solidus = f.solidus;
  k.temperature = f.temperature;
  k.ambient = f.ambient;
  k.viscosity = f.viscosity;
  k.viscositySolidus = f.viscositySolidus;
  k.tableScale = float(double(kViscosityEntries - 1) / (double(f.temperature) - f.solidus));
  // Geometric from the solidus's viscosity to the eruption's: an Arrhenius-like rise as it
  // cools, tabulated so that no shader evaluates a transcendental function.
  for (uint32_t i = 0; i < kViscosityEntries; ++i) {
    const double u = double(i) / double(kViscosityEntries - 1);
    k.table[i] = f.viscositySolidus == 0.0f
                     ? 0.0f
                     : float(double(f.viscositySolidus) *
                             std::pow(double(f.viscosity) / f.viscositySolidus, u));
  }
  k.table[0] = f.viscositySolidus;
  k.table[kViscosityEntries - 1] = f.viscosity;
  k.coolAir = float(h * f.coolingAir);
  k.coolContact = float(h * (double(f.coolingAir) + f.coolingGround));
  k.conduction = float(2.0 * f.conduction);
  return k;
}

std::vector<FlowWeights> flowWeights(const Scene& scene) {
  std::vector<FlowWeights> weights(scene.emitters.size());
  if (!scene.flow) return weights;
  const Flow& f = *scene.flow;
  const double radius = f.radius, r2 = radius * radius, v0 = restVolume(scene);
  const double s0 = std::cbrt(v0), lattice = v0 * latticeSum(s0, radius);
  const double poly6 = 945.0 / (32.0 * kPi * r2 * r2 * radius);  // -W'(r)/r = poly6 t^2
  // The implicit flow's Laplacian, exact on the rest lattice for a quadratic velocity:
  // sum V0 poly6 t^2 x^2 over the lattice is 1 in the continuum, and made 1 here.
  double quadratic = 0.0;
  forLattice(s0, radius, [&](int a, int, int, double r) {
    const double t = 1.0 - r * r / r2, x = double(a) * s0;
    quadratic += v0 * poly6 * t * t * x * x;
  });
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    const Emitter& e = scene.emitters[k];
    if (!e.flow) continue;
    const double v = double(e.mass) / f.density;
    const double density = v / lattice;
    weights[k] = {float(density),
                  float(3.0 * density / radius),
                  float(double(scene.h()) * v * poly6),
                  e.temperature == 0.0f ? f.temperature : e.temperature,
                  float(v * poly6 / quadratic),
                  float(v / v0)};
  }
  return weights;
}

std::vector<FlowRange> flowRanges(const Scene& scene) {
  std::vector<FlowRange> ranges;
  uint64_t index = 0;
  for (size_t e = 0; e < scene.emitters.size(); ++e) {
    if (!scene.emitters[e].flow) continue;
    ranges.push_back({scene.firstSlot(e), index, scene.emitters[e].particles});
    index += scene.emitters[e].particles;
  }
  return ranges;
}

gpu::FlowParams flowParams(const Scene& scene) {
  const FlowConstants k = flowConstants(scene);
  gpu::FlowParams p{};
  p.kernel = {k.invRadius, k.invRadius2, k.touch2, k.pressure};
  p.heat = {k.solidus, k.temperature, k.ambient, k.tableScale};
  p.rates = {k.viscosity, k.viscositySolidus, k.coolAir, k.coolContact};
  p.contact = {k.conduction, scene.flow->restitution, 0.0f, 0.0f};
  p.limits = {kPairCut, kTinyTerm, kCoincident, kCellLimit};
  for (uint32_t i = 0; i < kViscosityEntries; ++i) p.table[i / 4][i % 4] = k.table[i];
  const std::vector<FlowWeights> weights = flowWeights(scene);
  uint32_t n = 0;
  uint64_t slots = 0;
  for (size_t e = 0; e < scene.emitters.size(); ++e) {
    if (!scene.emitters[e].flow) continue;
    const FlowWeights& w = weights[e];
    p.emitters[n].weights = {w.density, w.pressure, w.laplacian, w.birth};
    p.emitters[n].slots = {uint32_t(e), uint32_t(slots), uint32_t(scene.firstSlot(e)),
                           scene.emitters[e].particles};
    const Lattice lattice = flowLattice(scene, e);
    p.emitters[n].lattice = lattice.shape;
    p.emitters[n].spacing = lattice.spacing;
    slots += scene.emitters[e].particles;
    ++n;
  }
  p.sizes = {flowBuckets(slots), uint32_t(slots), n, 0u};
  return p;
}

Cell cellOf(float x, float y, float z, float invRadius) {
  auto axis = [invRadius](float p) {
    const float u = std::min(std::max(p * invRadius, -kCellLimit), kCellLimit - 1.0f);
    return int32_t(std::floor(u));
  };
  return {axis(x), axis(y), axis(z)};
}

uint32_t bucketOf(const Cell& c, uint32_t buckets) {
  return ((uint32_t(c.x) * 73856093u) ^ (uint32_t(c.y) * 19349663u) ^ (uint32_t(c.z) * 83492791u)) &
         (buckets - 1u);
}

uint32_t flowBuckets(uint64_t slots) {
  static_assert(1024 % (gpu::kFlowRun * gpu::kFlowBlock) == 0,
                "flow.comp's scan takes whole blocks of whole runs");
  uint32_t buckets = 1024;
  while (buckets < 2 * slots && buckets < (1u << 30)) buckets *= 2;
  return buckets;
}

float flowViscosity(const FlowConstants& k, float t) {
  if (t >= k.temperature) return k.viscosity;
  if (t <= k.solidus) return k.viscositySolidus;
  const float x = (t - k.solidus) * k.tableScale;
  const uint32_t i = std::min(uint32_t(x), kViscosityEntries - 2);
  const float f = x - float(i);
  return k.table[i] + f * (k.table[i + 1] - k.table[i]);
}

FlowStepper::FlowStepper(const Reference& reference, unsigned threads)
    : reference_(reference),
      contact_(reference.scene()),
      k_(flowConstants(reference.scene())),
      workers_(std::max(threads, 1u)) {
  const Scene& s = reference.scene();
  contact_.restitution = s.flow->restitution;
  for (Collider& c : contact_.colliders) c.restitution = s.flow->restitution;
  uint64_t slots = 0;
  emitterOfSlot_.assign(s.particles(), kNotFlow);
  weights_ = flowWeights(s);
  for (size_t e = 0; e < s.emitters.size(); ++e) {
    if (!s.emitters[e].flow) continue;
    const uint64_t first = s.firstSlot(e);
    std::fill_n(emitterOfSlot_.begin() + first, s.emitters[e].particles, uint32_t(e));
    slots += s.emitters[e].particles;
  }
  buckets_ = flowBuckets(slots);
  const size_t n = s.particles();
  if (s.flow->solver == FlowSolver::Implicit) {
    ik_ = implicitConstants(s);
    bucketCap_ = ik_.bucketCap;
    indexOf_.assign(n, kNotFlow);
    for (size_t i = 0; i < n; ++i)
      if (emitterOfSlot_[i] != kNotFlow) {
        indexOf_[i] = uint32_t(flowSlots_.size());
        flowSlots_.push_back(uint32_t(i));
      }
    const size_t flow = flowSlots_.size();
    links_.resize(flow * ik_.cap);
    slopes_.resize(flow * ik_.cap);
    kernels_.resize(flow * ik_.cap);
    own_.resize(flow);
    pressure_.resize(flow);
    for (std::vector<float>* v : {&lambda_, &rhs_, &lambdaP_, &rhsP_}) v->resize(flow);
    for (unsigned k = 0; k < 2; ++k) {
      for (std::vector<float>* v : {&ar_[k], &az_[k], &ap_[k], &aq_[k]}) v->resize(flow);
      // A spare each: the products' 16-byte loads (cpu_implicit.cpp, X3).
      for (std::vector<V3f>* v : {&u_[k], &w_[k]}) v->resize(flow + 1);
    }
    pseudo_.resize(flow);
    count_.resize(flow);
    first_.resize(flow);
    at_.resize(flow);
    place_.resize(flow);
    indexAt_.resize(flow);
    terms_.resize(flow);
    for (std::vector<V3f>* v : {&r_, &z_, &q_, &b_}) v->resize(flow);
    for (std::vector<V3f>* v : {&gradWall_, &p_, &v_}) v->resize(flow + 1);  // as u_'s spare
  }
  cells_.resize(n);
  if (!flowSlots_.empty()) return;  // the explicit flow's own per-slot results
  for (std::vector<float>* v : {&theta_, &pi_, &viscosity_, &viscous_, &conductive_}) v->resize(n);
  touches_.resize(n);
}

// Alive flow slots sorted by bucket, and within a bucket by slot: a counting sort, stable
// in slot order.
void FlowStepper::sort(const State& state) {
  start_.assign(buckets_ + 1, 0);
  sorted_.clear();
  for (size_t i = 0; i < state.particles.size(); ++i) {
    const Particle& p = state.particles[i];
    if (emitterOfSlot_[i] == kNotFlow || p.age < 0.0f) continue;
    cells_[i] = cellOf(p.px, p.py, p.pz, k_.invRadius);
    ++start_[bucketOf(cells_[i], buckets_) + 1];
  }
  for (uint32_t b = 0; b < buckets_; ++b) start_[b + 1] += start_[b];
  sorted_.resize(start_[buckets_]);
  cursor_.assign(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < state.particles.size(); ++i)
    if (emitterOfSlot_[i] != kNotFlow && !(state.particles[i].age < 0.0f))
      sorted_[cursor_[bucketOf(cells_[i], buckets_)]++] = uint32_t(i);
  entries_.resize(sorted_.size());
  for (size_t e = 0; e < sorted_.size(); ++e) {
    const Particle& p = state.particles[sorted_[e]];
    entries_[e] = {p.px, p.py, p.pz, cells_[sorted_[e]]};
  }
}

// The entries neighbours() reads for a particle of cell c, in its order: the cells around
// c (aroundCell), each bucket's first bucketCap_ entries that lie in that cell.
void FlowStepper::candidates(const Cell& c, Candidates& out) const {
  out.cell = c;
  out.filled = true;
  out.x.clear();
  out.y.clear();
  out.z.clear();
  out.slot.clear();
  aroundCell(c, [&](const Cell& n, uint32_t begin, uint32_t count, bool centre) {
    for (uint32_t r = 0; r < std::min(count, bucketCap_); ++r) {
      const Entry& o = entries_[begin + r];
      if (!(o.cell == n)) continue;
      out.x.push_back(o.x);
      out.y.push_back(o.y);
      out.z.push_back(o.z);
      out.slot.push_back(sorted_[begin + r]);
    }
    if (!centre) return;
    out.centreEnd = uint32_t(out.slot.size());
    out.overflows = count > bucketCap_;
    out.centreLast = out.overflows ? sorted_[begin + bucketCap_ - 1] : 0;
  });
}

void FlowStepper::found(const State& state, size_t i, const Candidates& near, Found& out) const {
  const Particle& p = state.particles[i];
  const size_t most = near.slot.size() + 1;  // and i itself beyond its bucket's first
  if (out.slot.size() < most) {
    out.slot.resize(most);
    for (std::vector<float>* v : {&out.dx, &out.dy, &out.dz, &out.q, &out.t, &out.r, &out.nx,
                                  &out.ny, &out.nz})
      v->resize(most);
  }
  uint32_t k = 0;
  const auto offer = [&](uint32_t j, float x, float y, float z) {
    const V d{p.px - x, p.py - y, p.pz - z};
    const float q = dot(d, d);
    const float t = 1.0f - q * k_.invRadius2;
    out.slot[k] = j;
    out.dx[k] = d.x;
    out.dy[k] = d.y;
    out.dz[k] = d.z;
    out.q[k] = q;
    out.t[k] = t;
    k += unsigned(t > kPairCut);
  };
  for (uint32_t c = 0; c < near.centreEnd; ++c) offer(near.slot[c], near.x[c], near.y[c], near.z[c]);
  if (near.overflows && i > near.centreLast) offer(uint32_t(i), p.px, p.py, p.pz);
  for (uint32_t c = near.centreEnd; c < near.slot.size(); ++c)
    offer(near.slot[c], near.x[c], near.y[c], near.z[c]);
  out.count = k;
  for (uint32_t m = 0; m < k; ++m) {  // distance(), without its branch
    const float q = out.q[m], inv = Model::inverseRoot(q);
    const bool coincident = !(q >= kCoincident);
    out.nx[m] = coincident ? (i < out.slot[m] ? -1.0f : 1.0f) : inv * out.dx[m];
    out.ny[m] = coincident ? 0.0f : inv * out.dy[m];
    out.nz[m] = coincident ? 0.0f : inv * out.dz[m];
    out.r[m] = coincident ? 0.0f : q * inv;
  }
}

void FlowStepper::births(State& state, const std::vector<std::vector<Births>>& schedule,
                         size_t i) const {
  const Scene& s = reference_.scene();
  for (size_t k = 0; k < s.emitters.size(); ++k) {
    if (!s.emitters[k].flow) continue;
    const Births& b = schedule[k][i];
    const uint32_t capacity = s.emitters[k].particles;
    for (uint32_t r = 0; r < b.count; ++r) {
      const uint64_t slot = s.firstSlot(k) + (uint64_t(b.head) + r) % capacity;
      reference_.emit(k, b.firstSerial + r, state.particles[slot]);
      state.temperature[slot] = weights_[k].birth;
      state.crust[slot] = 0;
      if (!state.pressure.empty()) state.pressure[slot] = 0.0f;
    }
  }
}

// A flow particle holding a NaN or infinity dies before any neighbour reads it
// (docs/model.md "Non-finite values").
void FlowStepper::killNonFinite(State& state) const {
  for (size_t i = 0; i < state.particles.size(); ++i) {
    Particle& p = state.particles[i];
    if (emitterOfSlot_[i] == kNotFlow || p.age < 0.0f ||
        !Model::nonFinite(V{p.px, p.py, p.pz}, V{p.vx, p.vy, p.vz}))
      continue;
    p = Particle{0.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, 0.0f, p.mass};
    state.temperature[i] = 0.0f;
    state.crust[i] = 0;
    if (!state.pressure.empty()) state.pressure[i] = 0.0f;
  }
}

void FlowStepper::explicitRates(const State& state) {
  const std::vector<float>& temperature = state.temperature;
  const std::vector<uint8_t>& crust = state.crust;
  for (uint32_t i : sorted_) viscosity_[i] = flowViscosity(k_, temperature[i]);
  // Pass 1: the density ratio theta, the exchange rates of viscosity and conduction, and
  // whether a solid particle touches crust.
  parallel(sorted_.size(), [&](size_t e) {
    const uint32_t i = sorted_[e];
    float theta = 0.0f, viscous = 0.0f, conductive = 0.0f;
    bool touches = false;
    const float nu = viscosity_[i];
    neighbours(state, i, [&](uint32_t j, const V& d, float q, float t) {
      const FlowWeights& w = weights_[emitterOfSlot_[j]];
      V n;
      const float tr = std::max(1.0f - distance(q, d, uint32_t(i), j, n) * k_.invRadius, 0.0f);
      theta = theta + w.density * ((tr * tr) * tr);
      if (j == i) return;
      const float t2 = t * t;
      viscous = viscous + tiny((w.laplacian * (nu + viscosity_[j])) * t2);
      conductive = conductive + tiny(w.laplacian * t2);
      touches = touches || (crust[j] != 0 && q < k_.touch2);
    });
    theta_[i] = theta;
    const float inverse = reciprocal(theta);
    pi_[i] = ((k_.pressure * std::max(theta - 1.0f, 0.0f)) * inverse) * inverse;
    viscous_[i] = stable(viscous);
    conductive_[i] = stable(k_.conduction * conductive);
    touches_[i] = touches;
  });
}

void FlowStepper::explicitMove(const State& state) {
  const Scene& s = reference_.scene();
  const float h = s.h();
  const std::vector<Particle>& particles = state.particles;
  const std::vector<float>& temperature = state.temperature;
  const std::vector<uint8_t>& crust = state.crust;
  // Pass 2 and the step: every particle reads the start-of-step state of the others.
  next_.resize(sorted_.size());
  parallel(sorted_.size(), [&](size_t e) {
    const uint32_t i = sorted_[e];
    const size_t emitter = emitterOfSlot_[i];
    const Particle& p = particles[i];
    const bool isCrust = crust[i] != 0;
    const bool liquid = !isCrust && temperature[i] > k_.solidus;
    V a{0.0f, 0.0f, 0.0f}, dv{0.0f, 0.0f, 0.0f};
    float dT = 0.0f;
    neighbours(state, i, [&](uint32_t j, const V& d, float q, float t) {
      if (j == i) return;
      const FlowWeights& w = weights_[emitterOfSlot_[j]];
      const Particle& o = particles[j];
      const float t2 = t * t;
      dT = dT + tiny(((w.laplacian * k_.conduction) * t2) *
                     std::min(conductive_[i], conductive_[j]) * (temperature[j] - temperature[i]));
      if (!liquid) return;
      V n;
      const float tr = std::max(1.0f - distance(q, d, i, j, n) * k_.invRadius, 0.0f);
      const float push = (w.pressure * (pi_[i] + pi_[j])) * (tr * tr);
      a = a + V{tiny(push * n.x), tiny(push * n.y), tiny(push * n.z)};
      const float rate = ((w.laplacian * (viscosity_[i] + viscosity_[j])) * t2) *
                         std::min(viscous_[i], viscous_[j]);
      dv = dv +
           V{tiny(rate * (o.vx - p.vx)), tiny(rate * (o.vy - p.vy)), tiny(rate * (o.vz - p.vz))};
    });

    const V x0{p.px, p.py, p.pz};
    V x = x0, v{p.vx, p.vy, p.vz};
    bool touched = false, becomesCrust = isCrust, dies = false;
    if (!isCrust) {
      const EmitterConstants& ek = reference_.constants(emitter);
      if (liquid) {  // viscosity, then a semi-implicit Euler step with pressure and the forces
        v = Model::flushed(v + dv);
        const V f = Model::force<Modules::Any>(s, x, v, ek.w);
        v = Model::flushed((v + ek.hm * f) + h * a);
        x = x + h * v;
      } else if (touches_[i]) {  // a solid touching crust: crust where it is
        becomesCrust = true;
      } else {  // a cinder: falls as any particle
        v = Model::flushed(v + ek.hm * Model::force<Modules::Any>(s, x, v, ek.w));
        x = x + h * v;
      }
      touched = settle(contact_, reference_, x0, liquid, x, v, becomesCrust, dies);
    }
    const float cool = touched ? k_.coolContact : k_.coolAir;
    float age, t1;
    finish(s.emitters[emitter], k_.ambient, h, cool, p.age, temperature[i], dT, dies, age, t1,
           becomesCrust);
    next_[e] = {{x.x, x.y, x.z, age, v.x, v.y, v.z, p.mass}, t1, uint8_t(becomesCrust ? 1 : 0)};
  });
}

void FlowStepper::step(State& state) {
  if (!flowSlots_.empty()) return implicitStep(state);
  killNonFinite(state);
  sort(state);
  explicitRates(state);
  explicitMove(state);
  std::vector<Particle>& particles = state.particles;
  for (size_t e = 0; e < sorted_.size(); ++e) {
    const uint32_t i = sorted_[e];
    particles[i] = next_[e].particle;
    state.temperature[i] = next_[e].temperature;
    state.crust[i] = next_[e].crust;
  }
}

}  // namespace lava::detail
