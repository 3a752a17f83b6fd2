// The CPU reference of SPEC §6, one particle at a time, written apart from step.comp in
// plain float32 C++ (built with -ffp-contract=off): every operation in the order the spec
// gives, so that a conforming driver computes the same bits.
#include "reference.h"

#include <cmath>
#include <cstring>

#include "constants.h"
#include "shared.h"

namespace lava::detail {
namespace {

struct V {
  float x, y, z;
};
V operator+(V a, V b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V operator-(V a, V b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V operator*(float s, V a) {
  return {s * a.x, s * a.y, s * a.z};
}
float dot(V a, V b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
V of(const Vec3& v) {
  return {v.x, v.y, v.z};
}
float& at(V& v, int i) {
  return i == 0 ? v.x : i == 1 ? v.y : v.z;
}

float flushed(float v) {
  return std::fabs(v) < gpu::kTinySpeed ? 0.0f : v;
}
V flushed(V v) {
  return {flushed(v.x), flushed(v.y), flushed(v.z)};
}
float rest(float v) {
  return std::fabs(v) < gpu::kRestSpeed ? 0.0f : v;
}

float draw(uint32_t seed, uint64_t serial, uint32_t component) {
  return gpu::signedUnit(gpu::randomBits(seed, static_cast<uint32_t>(serial),
                                         static_cast<uint32_t>(serial >> 32), component));
}

// The emitter's offset for this serial (SPEC §6 "Emission").
V offset(const Emitter& e, uint32_t seed, uint64_t serial) {
  const uint32_t c = gpu::kVelocityComponents;
  switch (e.shape) {
    case Shape::Point:
      return {0.0f, 0.0f, 0.0f};
    case Shape::Disc:
      for (uint32_t t = 0; t < gpu::kDiscTries; ++t) {
        const float a = draw(seed, serial, c + 2 * t), b = draw(seed, serial, c + 2 * t + 1);
        if (a * a + b * b <= 1.0f) return {e.radius * a, 0.0f, e.radius * b};
      }
      return {e.radius * 0.0f, 0.0f, e.radius * 0.0f};
    case Shape::Sphere:
      for (uint32_t t = 0; t < gpu::kSphereTries; ++t) {
        const V u{draw(seed, serial, c + 3 * t), draw(seed, serial, c + 3 * t + 1),
                  draw(seed, serial, c + 3 * t + 2)};
        if (dot(u, u) <= 1.0f) return e.radius * u;
      }
      return e.radius * V{0.0f, 0.0f, 0.0f};
    case Shape::Box:
      return {e.size.x * draw(seed, serial, c), e.size.y * draw(seed, serial, c + 1),
              e.size.z * draw(seed, serial, c + 2)};
  }
  return {0.0f, 0.0f, 0.0f};
}

}  // namespace

// F(x, v) = ((wind.x, w, wind.z) - drag v) + the forces in order.
static V force(const Scene& s, V x, V v, float w) {
  V f = V{s.wind.x, w, s.wind.z} - s.drag * v;
  for (const Force& F : s.forces) {
    if (F.type == ForceType::Attractor) {
      const V d = of(F.position) - x;
      if (F.radius == 0.0f || dot(d, d) <= F.radius * F.radius) f = f + F.strength * d;
    } else {
      const V d = x - of(F.position);
      const V a = of(F.axis);
      const V c{a.y * d.z - a.z * d.y, a.z * d.x - a.x * d.z, a.x * d.y - a.y * d.x};
      f = f + F.strength * c;
    }
  }
  return f;
}

namespace {

// R(n, restitution, friction) after the position was projected.
V respond(V v, V n, float restitution, float friction) {
  const float vn = dot(v, n);
  if (!(vn < 0.0f)) return v;
  const V t = v - vn * n;
  const V kept{rest(friction * t.x), rest(friction * t.y), rest(friction * t.z)};
  const float e = -(restitution * vn);
  return kept + e * n;
}

// 1/sqrt(q), q > 0: the initial guess from the bit pattern, then three Newton steps.
float inverseRoot(float q) {
  uint32_t bits;
  std::memcpy(&bits, &q, 4);
  bits = gpu::kRsqrtMagic - (bits >> 1);
  float y;
  std::memcpy(&y, &bits, 4);
  const float half = 0.5f * q;
  for (int i = 0; i < 3; ++i) y = y * (1.5f - (half * y) * y);
  return y;
}

void cone(const Collider& c, const ConeConstants& k, V& x, V& v) {
  const V d = x - of(c.position);
  if (!(d.y >= 0.0f && d.y < c.height)) return;
  const float ry = c.baseRadius + k.slope * d.y;
  const float q = d.x * d.x + d.z * d.z;
  if (!(q < ry * ry)) return;
  float rx = 1.0f, rz = 0.0f, rho = 0.0f;
  if (q >= gpu::kAxisSquared) {
    const float inv = inverseRoot(q);
    rx = d.x * inv;
    rz = d.z * inv;
    rho = q * inv;
  }
  const float side = (ry - rho) * k.radial;
  const float up = c.height - d.y;
  V n;
  if (up <= side) {
    x.y = k.capY;
    n = {0.0f, 1.0f, 0.0f};
  } else {
    n = {k.radial * rx, k.vertical, k.radial * rz};
    x = x + (side + k.margin) * n;
  }
  v = flushed(respond(v, n, c.restitution, c.friction));
}

void collide(const Collider& c, const Vec3& normal, const ConeConstants& k, V& x, V& v) {
  switch (c.type) {
    case ColliderType::Plane: {
      const V n = of(normal);
      const float dist = dot(x - of(c.position), n);
      if (dist < 0.0f) {
        x = x - dist * n;
        v = flushed(respond(v, n, c.restitution, c.friction));
      }
      return;
    }
    case ColliderType::Sphere: {
      const V d = x - of(c.position);
      const float q = dot(d, d);
      if (q < c.radius * c.radius) {
        V n{0.0f, 1.0f, 0.0f};
        if (q != 0.0f) {
          const float s = std::sqrt(q);
          n = {d.x / s, d.y / s, d.z / s};
        }
        x = of(c.position) + c.radius * n;
        v = flushed(respond(v, n, c.restitution, c.friction));
      }
      return;
    }
    case ColliderType::Box: {
      V d = x - of(c.position);
      V e = of(c.size);
      if (std::fabs(d.x) < e.x && std::fabs(d.y) < e.y && std::fabs(d.z) < e.z) {
        const float gap[3] = {e.x - std::fabs(d.x), e.y - std::fabs(d.y), e.z - std::fabs(d.z)};
        int j = 0;
        for (int i = 1; i < 3; ++i)
          if (gap[i] < gap[j]) j = i;  // the least gap; ties keep the lowest axis
        const float sigma = at(d, j) >= 0.0f ? 1.0f : -1.0f;
        V center = of(c.position);
        at(x, j) = at(center, j) + sigma * at(e, j);
        V n{0.0f, 0.0f, 0.0f};
        at(n, j) = sigma;
        v = flushed(respond(v, n, c.restitution, c.friction));
      }
      return;
    }
    case ColliderType::Cone:
      cone(c, k, x, v);
      return;
  }
}

}  // namespace

Reference::Reference(const Scene& scene) : scene_(scene) {
  bool lifetimes = false;
  for (const Emitter& e : scene.emitters) lifetimes = lifetimes || e.lifetime > 0.0f;
  modules_ = scene.integrator == Integrator::ExplicitEuler && scene.forces.empty() &&
                     scene.colliders.empty() && !lifetimes
                 ? Modules::Euler
                 : Modules::Any;
  for (size_t k = 0; k < scene.emitters.size(); ++k)
    emitters_.push_back(emitterConstants(scene, k));
  for (const Collider& c : scene.colliders) {
    normals_.push_back(c.type == ColliderType::Plane ? unitNormal(c.normal) : Vec3{});
    cones_.push_back(c.type == ColliderType::Cone ? coneConstants(c) : ConeConstants{});
  }
}

void Reference::emit(size_t emitter, uint64_t serial, Particle& q) const {
  const Emitter& e = scene_.emitters[emitter];
  const uint32_t seed = scene_.seed + static_cast<uint32_t>(emitter);
  const V u{draw(seed, serial, 0), draw(seed, serial, 1), draw(seed, serial, 2)};
  const V x = of(e.position) + offset(e, seed, serial);
  const V v = flushed(V{e.velocity.x + e.spread.x * u.x, e.velocity.y + e.spread.y * u.y,
                        e.velocity.z + e.spread.z * u.z});
  q = {x.x, x.y, x.z, 0.0f, v.x, v.y, v.z, e.mass};
}

void Reference::step(size_t emitter, Particle& q) const {
  stepWith<Modules::Any>(emitter, q);
}

template <Reference::Modules M>
void Reference::stepWith(size_t emitter, Particle& q) const {
  if (q.age < 0.0f) return;
  const Scene& s = scene_;
  const EmitterConstants& k = emitters_[emitter];
  const float h = s.h();
  V x{q.px, q.py, q.pz};
  V v{q.vx, q.vy, q.vz};
  const V f = M == Modules::Euler ? V{s.wind.x, k.w, s.wind.z} - s.drag * v : force(s, x, v, k.w);
  switch (M == Modules::Euler ? Integrator::ExplicitEuler : s.integrator) {
    case Integrator::ExplicitEuler: {  // the seed: position with the start-of-step velocity
      const V x1 = x + h * v;
      v = v + k.hm * f;
      x = x1;
      break;
    }
    case Integrator::SemiImplicitEuler:
      v = v + k.hm * f;
      x = x + h * v;
      break;
    case Integrator::VelocityVerlet: {
      const V x1 = (x + h * v) + k.hh * f;
      const V half = v + k.hm * f;
      const V f1 = force(s, x1, half, k.w);
      v = v + k.hk * (f + f1);
      x = x1;
      break;
    }
  }
  v = flushed(v);
  float age = q.age + h;

  // The ground (seed eq. 7): restitution on y, retention alpha on x and z, and static
  // friction below kRestSpeed.
  if (x.y < 0.0f) {
    x.y = 0.0f;
    if (v.y < 0.0f) {
      v.x = rest(s.friction * v.x);
      v.z = rest(s.friction * v.z);
      v.y = -(s.restitution * v.y);
      v = flushed(v);
    }
  }
  if (M == Modules::Any) {
    for (size_t i = 0; i < s.colliders.size(); ++i)
      collide(s.colliders[i], normals_[i], cones_[i], x, v);
    const float lifetime = s.emitters[emitter].lifetime;
    if (lifetime > 0.0f && age >= lifetime) age = -1.0f;
  }
  q = {x.x, x.y, x.z, age, v.x, v.y, v.z, q.mass};
}

// Flattened: the step is inlined into the loop over the block, so the independent chains of
// neighbouring particles overlap in the CPU's pipeline (6x faster than calls on x86).
template <Reference::Modules M>
[[gnu::flatten]] void Reference::runWith(size_t emitter, const std::vector<Births>& schedule,
                                         uint32_t first, Particle* slots, size_t count) const {
  const uint32_t capacity = scene_.emitters[emitter].particles;
  for (const Births& b : schedule)
    for (size_t j = 0; j < count; ++j) {
      const uint32_t slot = first + static_cast<uint32_t>(j);
      const uint32_t rel = slot >= b.head ? slot - b.head : slot + capacity - b.head;
      if (rel < b.count) emit(emitter, b.firstSerial + rel, slots[j]);
      stepWith<M>(emitter, slots[j]);
    }
}

void Reference::run(size_t emitter, const std::vector<Births>& schedule, uint32_t first,
                    Particle* slots, size_t count) const {
  if (modules_ == Modules::Euler)
    runWith<Modules::Euler>(emitter, schedule, first, slots, count);
  else
    runWith<Modules::Any>(emitter, schedule, first, slots, count);
}

void emitParticle(const Scene& scene, size_t emitter, uint64_t serial, Particle& particle) {
  Reference(scene).emit(emitter, serial, particle);
}

void stepParticle(const Scene& scene, size_t emitter, Particle& particle) {
  Reference(scene).step(emitter, particle);
}

}  // namespace lava::detail
