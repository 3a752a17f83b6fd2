// The model of docs/model.md for the CPU, written once over a lane type `Float`:
//   - the scalar reference is Model<float>, one particle (reference.cpp);
//   - cpu-simd is Model<Floats>, one particle per SIMD lane (simd.cpp, Highway).
// shaders/step.comp is the independent implementation both are checked against.
//
// Every + - * / below is one float32 operation in the order written: the files that include
// this one are built with -ffp-contract=off, so nothing fuses, and docs/model.md gives the
// same order. A branch of the model is a mask: select(m, yes, no) takes one of two computed
// sides, lane by lane, and none(m) skips work that no lane needs, which changes no result.
//
// A lane type provides + - * / and unary - with float converting to it; comparisons giving
// its mask, which has & | !; and abs, sqrt, select, none and rsqrtGuess (below for float).
//
// Highway compiles cpu-simd once per instruction set: this file is then included once per
// target, into that target's namespace (the toggle below is Highway's -inl.h convention).

#ifndef LAVA_SIM_MODEL_INL_COMMON_
#define LAVA_SIM_MODEL_INL_COMMON_
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "constants.h"
#include "lava/scene.h"
#include "reference.h"
#include "shared.h"

#if defined(_MSC_VER)
#define LAVA_LANES_INLINE __forceinline
#else
#define LAVA_LANES_INLINE inline __attribute__((always_inline))
#endif
#endif

#if defined(LAVA_SIM_MODEL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LAVA_SIM_MODEL_INL_H_
#undef LAVA_SIM_MODEL_INL_H_
#else
#define LAVA_SIM_MODEL_INL_H_
#endif

#ifdef HWY_NAMESPACE
HWY_BEFORE_NAMESPACE();
namespace lava::detail::HWY_NAMESPACE {
#else
namespace lava::detail::scalar {
#endif

// One lane: the scalar reference.
LAVA_LANES_INLINE float select(bool m, float yes, float no) {
  return m ? yes : no;
}
LAVA_LANES_INLINE bool none(bool m) {
  return !m;
}
LAVA_LANES_INLINE float abs(float v) {
  return std::fabs(v);
}
LAVA_LANES_INLINE float sqrt(float v) {
  return std::sqrt(v);
}
// The first guess of 1/sqrt(q) from q's bits: kRsqrtMagic - (bits >> 1).
LAVA_LANES_INLINE float rsqrtGuess(float q) {
  uint32_t bits;
  std::memcpy(&bits, &q, 4);
  bits = gpu::kRsqrtMagic - (bits >> 1);
  float y;
  std::memcpy(&y, &bits, 4);
  return y;
}

template <class Float>
struct Model {
  using Mask = decltype(std::declval<Float>() < std::declval<Float>());

  struct V3 {
    Float x, y, z;
    friend LAVA_LANES_INLINE V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend LAVA_LANES_INLINE V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend LAVA_LANES_INLINE V3 operator*(Float s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
    friend LAVA_LANES_INLINE Float dot(V3 a, V3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
    friend LAVA_LANES_INLINE V3 cross(V3 a, V3 b) {
      return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    }
    friend LAVA_LANES_INLINE V3 select(Mask m, V3 yes, V3 no) {
      return {select(m, yes.x, no.x), select(m, yes.y, no.y), select(m, yes.z, no.z)};
    }
  };
  static LAVA_LANES_INLINE V3 of(const Vec3& v) { return {v.x, v.y, v.z}; }

  // Speeds below kTinySpeed become 0 (no denormals reach the state).
  static LAVA_LANES_INLINE Float flushed(Float v) {
    return select(abs(v) < gpu::kTinySpeed, 0.0f, v);
  }
  static LAVA_LANES_INLINE V3 flushed(V3 v) { return {flushed(v.x), flushed(v.y), flushed(v.z)}; }
  // Tangential speeds below kRestSpeed after friction stop: static friction.
  static LAVA_LANES_INLINE Float rest(Float v) { return select(abs(v) < gpu::kRestSpeed, 0.0f, v); }

  // F(x, v) = ((wind.x, w, wind.z) - drag v) + the forces in order.
  template <Modules Use>
  static LAVA_LANES_INLINE V3 force(const Scene& s, V3 x, V3 v, float w) {
    V3 f = V3{s.wind.x, w, s.wind.z} - s.drag * v;
    if (Use == Modules::Euler) return f;
    for (const Force& g : s.forces) {
      if (g.type == ForceType::Attractor) {  // towards the point, within the radius (0: any)
        const V3 d = of(g.position) - x;
        const V3 pulled = f + g.strength * d;
        f = g.radius == 0.0f ? pulled : select(dot(d, d) <= g.radius * g.radius, pulled, f);
      } else {  // vortex: around the axis through the point
        f = f + g.strength * cross(of(g.axis), x - of(g.position));
      }
    }
    return f;
  }

  // R(n, restitution, friction) after the position was projected: particles moving into
  // the surface (vn < 0) bounce, the rest keep v.
  static LAVA_LANES_INLINE V3 respond(V3 v, V3 n, float restitution, float friction) {
    const Float vn = dot(v, n);
    if (none(vn < 0.0f)) return v;
    const V3 t = v - vn * n;
    const V3 kept{rest(friction * t.x), rest(friction * t.y), rest(friction * t.z)};
    const Float e = -(restitution * vn);
    return select(vn < 0.0f, kept + e * n, v);
  }

  // The ground y = 0 for the `active` lanes: restitution on y, friction on x and z. Returns
  // the lanes it moved.
  static LAVA_LANES_INLINE Mask ground(const Scene& s, V3& x, V3& v, Mask active) {
    const Mask below = active & (x.y < 0.0f);
    if (none(below)) return below;
    x.y = select(below, 0.0f, x.y);
    const V3 bounced =
        flushed(V3{rest(s.friction * v.x), -(s.restitution * v.y), rest(s.friction * v.z)});
    v = select(below & (v.y < 0.0f), bounced, v);
    return below;
  }

  // 1/sqrt(q), q > 0: the guess from the bit pattern, then three Newton steps.
  static LAVA_LANES_INLINE Float inverseRoot(Float q) {
    Float y = rsqrtGuess(q);
    const Float half = 0.5f * q;
    for (int i = 0; i < 3; ++i) y = y * (1.5f - (half * y) * y);
    return y;
  }

  // The solid truncated cone: out through the side along its normal, or onto the cap.
  static LAVA_LANES_INLINE Mask cone(const Collider& c, const ConeConstants& k, V3& x, V3& v,
                                     Mask active) {
    const V3 d = x - of(c.position);
    const Float ry = c.baseRadius + k.slope * d.y;
    const Float q = d.x * d.x + d.z * d.z;
    const Mask inside = active & (d.y >= 0.0f) & (d.y < c.height) & (q < ry * ry);
    if (none(inside)) return inside;
    const Mask offAxis = q >= gpu::kAxisSquared;  // on the axis: the radial direction is +x
    const Float inv = inverseRoot(q);
    const Float rx = select(offAxis, d.x * inv, 1.0f);
    const Float rz = select(offAxis, d.z * inv, 0.0f);
    const Float rho = select(offAxis, q * inv, 0.0f);
    const Float side = (ry - rho) * k.radial;
    const Float up = c.height - d.y;
    const Mask top = up <= side;
    const V3 n = select(top, V3{0.0f, 1.0f, 0.0f}, V3{k.radial * rx, k.vertical, k.radial * rz});
    const V3 moved = select(top, V3{x.x, k.capY, x.z}, x + (side + k.margin) * n);
    x = select(inside, moved, x);
    v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
    return inside;
  }

  // The box (centre c, half-extents size) for the `active` lanes: those inside are put out
  // on the face of the least gap and respond. Returns the lanes it moved.
  static LAVA_LANES_INLINE Mask box(const Collider& c, V3& x, V3& v, Mask active) {
    const V3 center = of(c.position);
    const Vec3& e = c.size;
    // A box whose bottom is at or below the ground stands on it: the ground closes its
    // bottom face, so the box holds from the ground up and its bottom is no exit.
    const bool standing = c.position.y <= e.y;
    const V3 d = x - center;
    const Float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    // Inside: strictly between the faces where a particle is put out (centre -+ size), so
    // that one put on a face is outside there; |x - centre| < size can round inside.
    const V3 lo = center - of(e), hi = center + of(e);
    const Mask under = x.y < hi.y;
    const Mask below = standing ? under : (under & (lo.y < x.y));
    const Mask inside =
        active & (lo.x < x.x) & (x.x < hi.x) & below & (lo.z < x.z) & (x.z < hi.z);
    if (none(inside)) return inside;
    const Float gx = e.x - ax, gy = e.y - (standing ? d.y : ay), gz = e.z - az;
    // Out through the face of the least gap; ties keep the lowest axis.
    const Mask yBeatsX = gy < gx;
    const Mask isZ = gz < select(yBeatsX, gy, gx);
    const Mask isY = !isZ & yBeatsX;
    const Mask isX = !(isY | isZ);
    const Float side = select(isZ, d.z, select(isY, standing ? e.y : d.y, d.x));
    const Float sigma = select(side >= 0.0f, 1.0f, -1.0f);
    const V3 moved{select(isX, center.x + sigma * e.x, x.x),
                   select(isY, center.y + sigma * e.y, x.y),
                   select(isZ, center.z + sigma * e.z, x.z)};
    const V3 n{select(isX, sigma, 0.0f), select(isY, sigma, 0.0f), select(isZ, sigma, 0.0f)};
    x = select(inside, moved, x);
    v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
    return inside;
  }

  // Collider c for the `active` lanes: those inside are put on its surface and respond.
  // Returns the lanes it moved.
  static LAVA_LANES_INLINE Mask collide(const Collider& c, const Vec3& normal,
                                        const ConeConstants& k, V3& x, V3& v, Mask active) {
    switch (c.type) {
      case ColliderType::Plane: {
        const V3 n = of(normal);
        const Float dist = dot(x - of(c.position), n);
        const Mask below = active & (dist < 0.0f);
        if (none(below)) return below;
        x = select(below, x - dist * n, x);
        v = select(below, flushed(respond(v, n, c.restitution, c.friction)), v);
        return below;
      }
      case ColliderType::Sphere: {
        const V3 center = of(c.position);
        const V3 d = x - center;
        const Float q = dot(d, d);
        const Mask inside = active & (q < c.radius * c.radius);
        if (none(inside)) return inside;
        const Float s = sqrt(q);
        const V3 n = select(q != 0.0f, V3{d.x / s, d.y / s, d.z / s}, V3{0.0f, 1.0f, 0.0f});
        x = select(inside, center + c.radius * n, x);
        v = select(inside, flushed(respond(v, n, c.restitution, c.friction)), v);
        return inside;
      }
      case ColliderType::Box:
        return box(c, x, v, active);
      case ColliderType::Cone:
        return cone(c, k, x, v, active);
    }
    return active & !active;
  }

  // Whether the lanes in `active` lie inside the ground or a collider.
  static LAVA_LANES_INLINE Mask insideASolid(const Scene& s, const Reference& r, V3 x,
                                             Mask active) {
    Mask inside = active & (x.y < 0.0f);
    for (size_t i = 0; i < s.colliders.size(); ++i) {
      V3 at = x, v{0.0f, 0.0f, 0.0f};
      const Mask in = collide(s.colliders[i], r.planeNormal(i), r.cone(i), at, v, active);
      inside = inside | in;
    }
    return inside;
  }

  // docs/model.md "Contact": the ground, then the colliders in the scene's order, round and
  // round, until every solid but the last to move a lane has found it outside since then;
  // at most kContactRounds rounds. A lane still unresolved takes back x0, its position at
  // the start of the step, with v = 0; or dies (age -1, x = v = 0) when x0 is inside a solid
  // too. `s` gives the restitutions (the flow's own for its particles). Returns the lanes
  // the solids moved.
  static LAVA_LANES_INLINE Mask contact(const Scene& s, const Reference& r, const V3& x0, V3& x,
                                        V3& v, Float& age, Mask active) {
    const size_t solids = s.colliders.size() + 1;
    Float clear = 0.0f;                       // solids in a row that found the lane outside
    Float need = static_cast<float>(solids);  // all of them, then all but the last mover
    Mask open = active, touched = active & !active;
    for (size_t visit = 0; visit < gpu::kContactRounds * solids; ++visit) {
      const size_t k = visit % solids;
      const Mask moved =
          k == 0 ? ground(s, x, v, open)
                 : collide(s.colliders[k - 1], r.planeNormal(k - 1), r.cone(k - 1), x, v, open);
      touched = touched | moved;
      clear = select(moved, 0.0f, clear + 1.0f);
      need = select(moved, static_cast<float>(solids - 1), need);
      open = open & (clear < need);
      if (none(open)) return touched;
    }
    const Mask lost = insideASolid(s, r, x0, open);
    const V3 zero{0.0f, 0.0f, 0.0f};
    x = select(open, select(lost, zero, x0), x);
    v = select(open, zero, v);
    age = select(lost, -1.0f, age);
    return touched;
  }

  // Whether any of the six components is NaN or infinite.
  static LAVA_LANES_INLINE Mask nonFinite(const V3& x, const V3& v) {
    const float most = 3.40282347e38f;  // FLT_MAX: NaN compares false, so it is not finite
    const Float ax = abs(x.x), ay = abs(x.y), az = abs(x.z);
    const Float bx = abs(v.x), by = abs(v.y), bz = abs(v.z);
    return !((ax <= most) & (ay <= most) & (az <= most) & (bx <= most) & (by <= most) &
             (bz <= most));
  }

  // One step of emitter `emitter`'s particles in the lanes: the integrator, the ground, the
  // colliders in order, the lifetime. Lanes not alive (age < 0) keep their state.
  // Use::Euler: the lab handout's crater scene (explicit Euler, no forces, colliders or lifetimes), the
  // same operations with the other modules' code left out.
  template <Modules Use>
  static LAVA_LANES_INLINE void step(const Reference& r, size_t emitter, V3& x, V3& v, Float& age) {
    const Mask alive = !(age < 0.0f);
    if (none(alive)) return;
    const Scene& s = r.scene();
    const EmitterConstants& k = r.constants(emitter);
    const Float h = s.h();
    const V3 f = force<Use>(s, x, v, k.w);
    V3 x1 = x, v1 = v;
    switch (Use == Modules::Euler ? Integrator::ExplicitEuler : s.integrator) {
      case Integrator::ExplicitEuler:  // the position moves with the start-of-step velocity
        x1 = x + h * v;
        v1 = v + k.hm * f;
        break;
      case Integrator::SemiImplicitEuler:
        v1 = v + k.hm * f;
        x1 = x + h * v1;
        break;
      case Integrator::VelocityVerlet: {
        x1 = (x + h * v) + k.hh * f;
        const V3 half = v + k.hm * f;
        v1 = v + k.hk * (f + force<Use>(s, x1, half, k.w));
        break;
      }
    }
    v1 = flushed(v1);
    Float age1 = age + h;
    // A NaN or infinity dies here, with x = v = 0 (docs/model.md "Non-finite values").
    const Mask nonFiniteLanes = nonFinite(x1, v1);
    const Mask broken = alive & nonFiniteLanes;
    const V3 zero{0.0f, 0.0f, 0.0f};
    x1 = select(broken, zero, x1);
    v1 = select(broken, zero, v1);
    age1 = select(broken, -1.0f, age1);
    if (Use == Modules::Any) {
      contact(s, r, x, x1, v1, age1, alive & !broken);
      const float lifetime = s.emitters[emitter].lifetime;
      if (lifetime > 0.0f) age1 = select(age1 >= lifetime, -1.0f, age1);
    } else {
      ground(s, x1, v1, alive & !broken);
    }
    x = select(alive, x1, x);
    v = select(alive, v1, v);
    age = select(alive, age1, age);
  }
};

}  // namespace
#ifdef HWY_NAMESPACE
HWY_AFTER_NAMESPACE();
#endif

#endif  // LAVA_SIM_MODEL_INL_H_
