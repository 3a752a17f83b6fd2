// The cpu-simd kernel (simd.h): the model (model-inl.h) on Highway vectors, one particle per
// lane. Highway compiles this file once per x86/Arm target (foreach_target.h) and the first
// call picks the best the CPU runs. Floats and Mask below are the lane types the model runs
// on: only Add, Sub, Mul, Div, Sqrt, Neg, Abs, comparisons and selects, never MulAdd, and the
// file is built with -ffp-contract=off, so no lane fuses a multiply with an add
// (SimdKernel.HasNoFusedMultiplyAdd checks the object code).
// Sizeless vectors (Arm SVE, RISC-V V) cannot be struct members, as Floats holds them: those
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

#include "lava/error.h"
#include "shared.h"
#include "simd.h"

HWY_BEFORE_NAMESPACE();
namespace lava::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;

// A block of particles, one array per field (Particle's order).
struct Block {
  HWY_ALIGN float px[kSimdBlock], py[kSimdBlock], pz[kSimdBlock], age[kSimdBlock];
  HWY_ALIGN float vx[kSimdBlock], vy[kSimdBlock], vz[kSimdBlock], mass[kSimdBlock];
};

// The model's lane types: a vector of floats (a float converts by broadcasting) and a mask.
struct Floats {
  hn::Vec<D> v;
  Floats() = default;
  HWY_INLINE Floats(float s) : v(hn::Set(D(), s)) {}  // NOLINT: implicit, as the model writes it
  HWY_INLINE explicit Floats(hn::Vec<D> lanes) : v(lanes) {}
};
struct Mask {
  hn::Mask<D> m;
};

HWY_INLINE Floats operator+(Floats a, Floats b) {
  return Floats(hn::Add(a.v, b.v));
}
HWY_INLINE Floats operator-(Floats a, Floats b) {
  return Floats(hn::Sub(a.v, b.v));
}
HWY_INLINE Floats operator*(Floats a, Floats b) {
  return Floats(hn::Mul(a.v, b.v));
}
HWY_INLINE Floats operator/(Floats a, Floats b) {
  return Floats(hn::Div(a.v, b.v));
}
HWY_INLINE Floats operator-(Floats a) {
  return Floats(hn::Neg(a.v));
}
HWY_INLINE Mask operator<(Floats a, Floats b) {
  return {hn::Lt(a.v, b.v)};
}
HWY_INLINE Mask operator<=(Floats a, Floats b) {
  return {hn::Le(a.v, b.v)};
}
HWY_INLINE Mask operator>=(Floats a, Floats b) {
  return {hn::Ge(a.v, b.v)};
}
HWY_INLINE Mask operator!=(Floats a, Floats b) {
  return {hn::Ne(a.v, b.v)};
}
HWY_INLINE Mask operator&(Mask a, Mask b) {
  return {hn::And(a.m, b.m)};
}
HWY_INLINE Mask operator|(Mask a, Mask b) {
  return {hn::Or(a.m, b.m)};
}
HWY_INLINE Mask operator!(Mask a) {
  return {hn::Not(a.m)};
}
HWY_INLINE Floats select(Mask m, Floats yes, Floats no) {
  return Floats(hn::IfThenElse(m.m, yes.v, no.v));
}
HWY_INLINE bool none(Mask m) {
  return hn::AllFalse(D(), m.m);
}
HWY_INLINE Floats abs(Floats a) {
  return Floats(hn::Abs(a.v));
}
HWY_INLINE Floats sqrt(Floats a) {
  return Floats(hn::Sqrt(a.v));
}
HWY_INLINE Floats rsqrtGuess(Floats q) {
  const hn::RebindToUnsigned<D> du;
  return Floats(hn::BitCast(
      D(), hn::Sub(hn::Set(du, gpu::kRsqrtMagic), hn::ShiftRight<1>(hn::BitCast(du, q.v)))));
}

}  // namespace HWY_NAMESPACE
}  // namespace lava::detail
HWY_AFTER_NAMESPACE();

#include "model-inl.h"

HWY_BEFORE_NAMESPACE();
namespace lava::detail {
namespace HWY_NAMESPACE {

// Model::step for the lanes at `i` of the block.
template <Modules Use>
HWY_INLINE void stepLanes(const Reference& r, size_t emitter, Block& b, size_t i) {
  using V3 = Model<Floats>::V3;
  const D d;
  V3 x{Floats(hn::Load(d, b.px + i)), Floats(hn::Load(d, b.py + i)), Floats(hn::Load(d, b.pz + i))};
  V3 v{Floats(hn::Load(d, b.vx + i)), Floats(hn::Load(d, b.vy + i)), Floats(hn::Load(d, b.vz + i))};
  Floats age(hn::Load(d, b.age + i));
  Model<Floats>::step<Use>(r, emitter, x, v, age);
  hn::Store(x.x.v, d, b.px + i);
  hn::Store(x.y.v, d, b.py + i);
  hn::Store(x.z.v, d, b.pz + i);
  hn::Store(age.v, d, b.age + i);
  hn::Store(v.x.v, d, b.vx + i);
  hn::Store(v.y.v, d, b.vy + i);
  hn::Store(v.z.v, d, b.vz + i);
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
    if (r.modules() == Modules::Euler)
      for (size_t i = 0; i < end; i += lanes) stepLanes<Modules::Euler>(r, emitter, b, i);
    else
      for (size_t i = 0; i < end; i += lanes) stepLanes<Modules::Any>(r, emitter, b, i);
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

std::vector<int64_t> available() {  // best first
  return hwy::SupportedAndGeneratedTargets();
}

// 0 (the best) made concrete.
int64_t resolved(SimdTarget target) {
  static const int64_t best = available().front();
  return target ? target : best;
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

#define LAVA_DISPATCH(name, target) (*HWY_DISPATCH_TABLE(name)[tableIndex(resolved(target))])

void simdRun(const Reference& reference, SimdTarget target, size_t emitter,
             const std::vector<Births>& schedule, uint32_t first, Particle* slots, size_t count) {
  LAVA_DISPATCH(Run, target)(reference, emitter, schedule, first, slots, count);
}

uint64_t stepKernelOnly(const Reference& reference, Particle* block, uint64_t steps, bool scalar,
                        SimdTarget target) {
  // Each kernel's own loop over a block and a schedule, with no births in it.
  const std::vector<Births> none(std::min<uint64_t>(steps, 4096), Births{0, 0, 0});
  for (uint64_t done = 0; done < steps;) {
    const uint64_t n = std::min<uint64_t>(steps - done, none.size());
    const std::vector<Births> batch(none.begin(), none.begin() + n);
    if (scalar)  // in blocks of 32, as CpuSimulation runs it
      for (size_t first = 0; first < kSimdBlock; first += kReferenceBlock)
        reference.run(0, batch, 0, block + first, kReferenceBlock);
    else
      simdRun(reference, target, 0, batch, 0, block, kSimdBlock);
    done += n;
  }
  return steps * kSimdBlock;
}

std::string simdTarget(SimdTarget target) {
  const size_t lanes = LAVA_DISPATCH(LaneCount, target)();
  return std::string(hwy::TargetName(LAVA_DISPATCH(Target, target)())) + " (" +
         std::to_string(lanes * 32) + "-bit, " + std::to_string(lanes) + " lanes)";
}

std::vector<std::string> simdTargets() {
  std::vector<std::string> names;
  for (int64_t t : available()) names.push_back(hwy::TargetName(t));
  return names;
}

SimdTarget simdTargetNamed(const std::string& name) {
  if (name.empty()) return 0;
  std::string known;
  for (int64_t t : available()) {
    if (name == hwy::TargetName(t)) return t;
    known += (known.empty() ? "" : ", ") + std::string(hwy::TargetName(t));
  }
  throw InvalidArgument("simd-target",
                        "expected one of " + known + " (this CPU's), got '" + name + "'");
}

#undef LAVA_DISPATCH

}  // namespace lava::detail
#endif
