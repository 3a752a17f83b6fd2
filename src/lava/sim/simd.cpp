// The cpu-simd kernel (simd.h): Reference::step written once more, on Highway vectors.
// Highway compiles this file once per x86/Arm target (foreach_target.h) and the first call
// picks the best the CPU runs. Each function below mirrors its scalar twin in
// reference.cpp operation for operation; a branch there is a mask here, with both sides
// computed and the taken one selected. Only Add, Sub, Mul, Div, Sqrt, Neg and comparisons
// are used, never MulAdd, and the file is built with -ffp-contract=off, so no lane fuses a
// multiply with an add (SimdKernel.HasNoFusedMultiplyAdd checks the object code).
// Sizeless vectors (Arm SVE, RISC-V V) cannot be struct members, as V3 holds them: those
// targets are left out (expanded lazily, after Highway defines the names). NEON, x86 and
// scalar are compiled.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sim/simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
//
#include <hwy/highway.h>

#include <algorithm>
#include <atomic>

#include "lava/error.h"
#include "shared.h"
#include "simd.h"

HWY_BEFORE_NAMESPACE();
namespace lava::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// A block of particles, one array per field (Particle's order).
struct Block {
  HWY_ALIGN float px[kSimdBlock], py[kSimdBlock], pz[kSimdBlock], age[kSimdBlock];
  HWY_ALIGN float vx[kSimdBlock], vy[kSimdBlock], vz[kSimdBlock], mass[kSimdBlock];
};

struct V3 {
  V x, y, z;
};

HWY_INLINE V splat(float value) {
  return hn::Set(D(), value);
}
HWY_INLINE V3 splat(const Vec3& v) {
  return {splat(v.x), splat(v.y), splat(v.z)};
}
HWY_INLINE V3 operator+(V3 a, V3 b) {
  return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
}
HWY_INLINE V3 operator-(V3 a, V3 b) {
  return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
}
HWY_INLINE V3 operator*(V s, V3 a) {
  return {hn::Mul(s, a.x), hn::Mul(s, a.y), hn::Mul(s, a.z)};
}
HWY_INLINE V dot(V3 a, V3 b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
HWY_INLINE V3 select(M m, V3 yes, V3 no) {
  return {hn::IfThenElse(m, yes.x, no.x), hn::IfThenElse(m, yes.y, no.y),
          hn::IfThenElse(m, yes.z, no.z)};
}

HWY_INLINE V flushed(V v) {
  return hn::IfThenZeroElse(hn::Lt(hn::Abs(v), splat(gpu::kTinySpeed)), v);
}
HWY_INLINE V3 flushed(V3 v) {
  return {flushed(v.x), flushed(v.y), flushed(v.z)};
}
HWY_INLINE V rest(V v) {
  return hn::IfThenZeroElse(hn::Lt(hn::Abs(v), splat(gpu::kRestSpeed)), v);
}

// F(x, v) = ((wind.x, w, wind.z) - drag v) + the forces in order.
HWY_INLINE V3 force(const Scene& s, V3 x, V3 v, float w) {
  V3 f = V3{splat(s.wind.x), splat(w), splat(s.wind.z)} - splat(s.drag) * v;
  for (const Force& F : s.forces) {
    if (F.type == ForceType::Attractor) {
      const V3 d = splat(F.position) - x;
      const V3 pulled = f + splat(F.strength) * d;
      if (F.radius == 0.0f)
        f = pulled;
      else
        f = select(hn::Le(dot(d, d), splat(F.radius * F.radius)), pulled, f);
    } else {
      const V3 d = x - splat(F.position);
      const V ax = splat(F.axis.x), ay = splat(F.axis.y), az = splat(F.axis.z);
      const V3 c{hn::Sub(hn::Mul(ay, d.z), hn::Mul(az, d.y)),
                 hn::Sub(hn::Mul(az, d.x), hn::Mul(ax, d.z)),
                 hn::Sub(hn::Mul(ax, d.y), hn::Mul(ay, d.x))};
      f = f + splat(F.strength) * c;
    }
  }
  return f;
}

// R(n, restitution, friction), lanes with vn >= 0 keeping v.
HWY_INLINE V3 respond(V3 v, V3 n, float restitution, float friction) {
  const V vn = dot(v, n);
  const V3 t = v - vn * n;
  const V fr = splat(friction);
  const V3 kept{rest(hn::Mul(fr, t.x)), rest(hn::Mul(fr, t.y)), rest(hn::Mul(fr, t.z))};
  const V e = hn::Neg(hn::Mul(splat(restitution), vn));
  return select(hn::Lt(vn, hn::Zero(D())), kept + e * n, v);
}

// 1/sqrt(q): the bit-pattern guess, then three Newton steps.
HWY_INLINE V inverseRoot(V q) {
  const hn::RebindToUnsigned<D> du;
  const auto bits = hn::Sub(hn::Set(du, gpu::kRsqrtMagic), hn::ShiftRight<1>(hn::BitCast(du, q)));
  V y = hn::BitCast(D(), bits);
  const V half = hn::Mul(splat(0.5f), q);
  for (int i = 0; i < 3; ++i) y = hn::Mul(y, hn::Sub(splat(1.5f), hn::Mul(hn::Mul(half, y), y)));
  return y;
}

HWY_INLINE void cone(const Collider& c, const ConeConstants& k, V3& x, V3& v) {
  const V3 d = x - splat(c.position);
  const V zero = hn::Zero(D());
  const V height = splat(c.height);
  const V ry = hn::Add(splat(c.baseRadius), hn::Mul(splat(k.slope), d.y));
  const V q = hn::Add(hn::Mul(d.x, d.x), hn::Mul(d.z, d.z));
  const M inside =
      hn::And(hn::And(hn::Ge(d.y, zero), hn::Lt(d.y, height)), hn::Lt(q, hn::Mul(ry, ry)));
  if (hn::AllFalse(D(), inside)) return;
  const M offAxis = hn::Ge(q, splat(gpu::kAxisSquared));
  const V inv = inverseRoot(q);
  const V rx = hn::IfThenElse(offAxis, hn::Mul(d.x, inv), splat(1.0f));
  const V rz = hn::IfThenElseZero(offAxis, hn::Mul(d.z, inv));
  const V rho = hn::IfThenElseZero(offAxis, hn::Mul(q, inv));
  const V radial = splat(k.radial);
  const V side = hn::Mul(hn::Sub(ry, rho), radial);
  const V up = hn::Sub(height, d.y);
  const M top = hn::Le(up, side);
  const V3 sideNormal{hn::Mul(radial, rx), splat(k.vertical), hn::Mul(radial, rz)};
  const V3 n = select(top, V3{zero, splat(1.0f), zero}, sideNormal);
  V3 moved = x + hn::Add(side, splat(k.margin)) * n;
  moved.y = hn::IfThenElse(top, splat(k.capY), moved.y);
  moved.x = hn::IfThenElse(top, x.x, moved.x);
  moved.z = hn::IfThenElse(top, x.z, moved.z);
  x = select(inside, moved, x);
  v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
}

HWY_INLINE void collide(const Collider& c, const Vec3& normal, const ConeConstants& k, V3& x,
                        V3& v) {
  const V zero = hn::Zero(D());
  switch (c.type) {
    case ColliderType::Plane: {
      const V3 n = splat(normal);
      const V dist = dot(x - splat(c.position), n);
      const M below = hn::Lt(dist, zero);
      x = select(below, x - dist * n, x);
      v = select(below, flushed(respond(v, n, c.restitution, c.friction)), v);
      return;
    }
    case ColliderType::Sphere: {
      const V3 center = splat(c.position);
      const V3 d = x - center;
      const V q = dot(d, d);
      const M inside = hn::Lt(q, splat(c.radius * c.radius));
      if (hn::AllFalse(D(), inside)) return;
      const V s = hn::Sqrt(q);
      const V3 n = select(hn::Ne(q, zero), V3{hn::Div(d.x, s), hn::Div(d.y, s), hn::Div(d.z, s)},
                          V3{zero, splat(1.0f), zero});
      x = select(inside, center + splat(c.radius) * n, x);
      v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
      return;
    }
    case ColliderType::Box: {
      const V3 center = splat(c.position);
      const V3 d = x - center;
      const V3 e = splat(c.size);
      const V ax = hn::Abs(d.x), ay = hn::Abs(d.y), az = hn::Abs(d.z);
      const M inside = hn::And(hn::And(hn::Lt(ax, e.x), hn::Lt(ay, e.y)), hn::Lt(az, e.z));
      if (hn::AllFalse(D(), inside)) return;
      const V gx = hn::Sub(e.x, ax), gy = hn::Sub(e.y, ay), gz = hn::Sub(e.z, az);
      // The least gap; ties keep the lowest axis.
      const M yBeatsX = hn::Lt(gy, gx);
      const M isZ = hn::Lt(gz, hn::IfThenElse(yBeatsX, gy, gx));
      const M isY = hn::AndNot(isZ, yBeatsX);
      const M isX = hn::Not(hn::Or(isY, isZ));
      const V dj = hn::IfThenElse(isZ, d.z, hn::IfThenElse(isY, d.y, d.x));
      const V sigma = hn::IfThenElse(hn::Ge(dj, zero), splat(1.0f), splat(-1.0f));
      V3 moved = x;
      moved.x = hn::IfThenElse(isX, hn::Add(center.x, hn::Mul(sigma, e.x)), x.x);
      moved.y = hn::IfThenElse(isY, hn::Add(center.y, hn::Mul(sigma, e.y)), x.y);
      moved.z = hn::IfThenElse(isZ, hn::Add(center.z, hn::Mul(sigma, e.z)), x.z);
      const V3 n{hn::IfThenElseZero(isX, sigma), hn::IfThenElseZero(isY, sigma),
                 hn::IfThenElseZero(isZ, sigma)};
      x = select(inside, moved, x);
      v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
      return;
    }
    case ColliderType::Cone:
      cone(c, k, x, v);
      return;
  }
}

// Reference::stepWith for the lanes at `i` of the block.
HWY_INLINE void stepLanes(const Reference& r, size_t emitter, Block& b, size_t i) {
  const D d;
  const Scene& s = r.scene();
  const EmitterConstants& k = r.constants(emitter);
  const V h = splat(s.h());
  const V age0 = hn::Load(d, b.age + i);
  const M alive = hn::Not(hn::Lt(age0, hn::Zero(d)));
  const V3 x0{hn::Load(d, b.px + i), hn::Load(d, b.py + i), hn::Load(d, b.pz + i)};
  const V3 v0{hn::Load(d, b.vx + i), hn::Load(d, b.vy + i), hn::Load(d, b.vz + i)};
  const V3 f = force(s, x0, v0, k.w);
  V3 x, v;
  switch (s.integrator) {
    case Integrator::ExplicitEuler:
      x = x0 + h * v0;
      v = v0 + splat(k.hm) * f;
      break;
    case Integrator::SemiImplicitEuler:
      v = v0 + splat(k.hm) * f;
      x = x0 + h * v;
      break;
    case Integrator::VelocityVerlet: {
      x = (x0 + h * v0) + splat(k.hh) * f;
      const V3 half = v0 + splat(k.hm) * f;
      const V3 f1 = force(s, x, half, k.w);
      v = v0 + splat(k.hk) * (f + f1);
      break;
    }
  }
  v = flushed(v);
  V age = hn::Add(age0, h);

  // The ground.
  const V zero = hn::Zero(d);
  const M below = hn::Lt(x.y, zero);
  x.y = hn::IfThenZeroElse(below, x.y);
  const M bounce = hn::And(below, hn::Lt(v.y, zero));
  const V fr = splat(s.friction);
  const V3 bounced = flushed(V3{rest(hn::Mul(fr, v.x)), hn::Neg(hn::Mul(splat(s.restitution), v.y)),
                                rest(hn::Mul(fr, v.z))});
  v = select(bounce, bounced, v);

  for (size_t c = 0; c < s.colliders.size(); ++c)
    collide(s.colliders[c], r.planeNormal(c), r.cone(c), x, v);
  const float lifetime = s.emitters[emitter].lifetime;
  if (lifetime > 0.0f) age = hn::IfThenElse(hn::Ge(age, splat(lifetime)), splat(-1.0f), age);

  hn::Store(hn::IfThenElse(alive, x.x, x0.x), d, b.px + i);
  hn::Store(hn::IfThenElse(alive, x.y, x0.y), d, b.py + i);
  hn::Store(hn::IfThenElse(alive, x.z, x0.z), d, b.pz + i);
  hn::Store(hn::IfThenElse(alive, age, age0), d, b.age + i);
  hn::Store(hn::IfThenElse(alive, v.x, v0.x), d, b.vx + i);
  hn::Store(hn::IfThenElse(alive, v.y, v0.y), d, b.vy + i);
  hn::Store(hn::IfThenElse(alive, v.z, v0.z), d, b.vz + i);
}

void put(Block& b, size_t j, const Particle& p) {
  b.px[j] = p.px, b.py[j] = p.py, b.pz[j] = p.pz, b.age[j] = p.age;
  b.vx[j] = p.vx, b.vy[j] = p.vy, b.vz[j] = p.vz, b.mass[j] = p.mass;
}

void load(Block& b, const Particle* slots, size_t count) {
  // Lanes past the slots: not alive, so the step leaves them be.
  for (size_t j = 0; j < kSimdBlock; ++j)
    put(b, j, j < count ? slots[j] : Particle{0, 0, 0, -1.0f, 0, 0, 0, 0});
}

void store(const Block& b, Particle* slots, size_t count) {
  for (size_t j = 0; j < count; ++j)
    slots[j] = {b.px[j], b.py[j], b.pz[j], b.age[j], b.vx[j], b.vy[j], b.vz[j], b.mass[j]};
}

// Lanes [0, count) rounded up to whole vectors (the block's lanes past count are dead).
size_t vectorsEnd(size_t count) {
  const size_t lanes = hn::Lanes(D());
  return (count + lanes - 1) / lanes * lanes;
}

void Run(const Reference& r, size_t emitter, const std::vector<Births>& schedule, uint32_t first,
         Particle* slots, size_t count) {
  Block b;
  load(b, slots, count);
  const uint32_t capacity = r.scene().emitters[emitter].particles;
  const size_t lanes = hn::Lanes(D()), end = vectorsEnd(count);
  for (const Births& births : schedule) {
    // Born: slots head, head + 1, ... (mod capacity); those in [first, first + count).
    for (uint32_t part = 0, head = births.head, left = births.count; left > 0 && part < 2; ++part) {
      const uint32_t run = std::min(left, capacity - head);  // [head, head + run) unwrapped
      const uint32_t from = std::max(head, first);
      const uint32_t to = static_cast<uint32_t>(std::min<uint64_t>(head + run, first + count));
      for (uint32_t slot = from; slot < to; ++slot) {
        Particle p;
        r.emit(emitter, births.firstSerial + (births.count - left) + (slot - head), p);
        put(b, slot - first, p);
      }
      left -= run;
      head = 0;
    }
    for (size_t i = 0; i < end; i += lanes) stepLanes(r, emitter, b, i);
  }
  store(b, slots, count);
}

int64_t Target() {
  return HWY_TARGET;
}
size_t LaneCount() {
  return hn::Lanes(D());
}

}  // namespace HWY_NAMESPACE
}  // namespace lava::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lava::detail {

HWY_EXPORT(Run);
HWY_EXPORT(Target);
HWY_EXPORT(LaneCount);

namespace {

// Lava's choice among the targets compiled here and run by this CPU, as Highway's target bit
// (0: the best). Lava indexes the HWY_EXPORT tables itself: Highway's own selection
// (GetChosenTarget, SupportedTargets) is never changed, so a host that uses Highway keeps its.
std::atomic<int64_t> chosenTarget{0};

std::vector<int64_t> available() {  // best first
  return hwy::SupportedAndGeneratedTargets();
}

int64_t target() {
  static const int64_t best = available().front();
  const int64_t chosen = chosenTarget.load();
  return chosen ? chosen : best;
}

// The entry of an HWY_EXPORT table that holds `target`'s function.
size_t tableIndex(int64_t target) {
#if (HWY_TARGETS & (HWY_TARGETS - 1)) == 0
  (void)target;
  return 0;  // one target compiled: a table of one
#else
  const int64_t shifted = HWY_CHOSEN_TARGET_SHIFT(target);
  return shifted ? hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<uint64_t>(shifted))
                 : HWY_MAX_DYNAMIC_TARGETS + 1;  // the fallback (EMU128 or SCALAR): last
#endif
}

}  // namespace

#define LAVA_DISPATCH(name) (*HWY_DISPATCH_TABLE(name)[tableIndex(target())])

void simdRun(const Reference& reference, size_t emitter, const std::vector<Births>& schedule,
             uint32_t first, Particle* slots, size_t count) {
  LAVA_DISPATCH(Run)(reference, emitter, schedule, first, slots, count);
}

uint64_t stepKernelOnly(const Reference& reference, Particle* block, uint64_t steps, bool scalar) {
  // Each kernel's own loop over a block and a schedule, with no births in it.
  const std::vector<Births> none(std::min<uint64_t>(steps, 4096), Births{0, 0, 0});
  for (uint64_t done = 0; done < steps;) {
    const uint64_t n = std::min<uint64_t>(steps - done, none.size());
    const std::vector<Births> batch(none.begin(), none.begin() + n);
    if (scalar)  // in blocks of 32, as CpuSimulation runs it
      for (size_t first = 0; first < kSimdBlock; first += kReferenceBlock)
        reference.run(0, batch, 0, block + first, kReferenceBlock);
    else
      simdRun(reference, 0, batch, 0, block, kSimdBlock);
    done += n;
  }
  return steps * kSimdBlock;
}

std::string simdTarget() {
  const size_t lanes = LAVA_DISPATCH(LaneCount)();
  return std::string(hwy::TargetName(LAVA_DISPATCH(Target)())) + " (" + std::to_string(lanes * 32) +
         "-bit, " + std::to_string(lanes) + " lanes)";
}

std::vector<std::string> simdTargets() {
  std::vector<std::string> names;
  for (int64_t t : available()) names.push_back(hwy::TargetName(t));
  return names;
}

void useSimdTarget(const std::string& name) {
  if (name.empty()) {
    chosenTarget = 0;
    return;
  }
  std::string known;
  for (int64_t t : available()) {
    if (name == hwy::TargetName(t)) {
      chosenTarget = t;
      return;
    }
    known += (known.empty() ? "" : ", ") + std::string(hwy::TargetName(t));
  }
  throw InvalidArgument("simd-target",
                        "expected one of " + known + " (this CPU's), got '" + name + "'");
}

#undef LAVA_DISPATCH

}  // namespace lava::detail
#endif
