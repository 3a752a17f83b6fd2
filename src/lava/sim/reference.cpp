// The CPU reference: model-inl.h on one particle at a time, with emission, and the loop
// CpuSimulation runs over a block of slots.
#include "reference.h"

#include "constants.h"
#include "model-inl.h"
#include "shared.h"

namespace lava::detail {
namespace {

using Model = scalar::Model<float>;
using V = Model::V3;

float draw(uint32_t seed, uint64_t serial, uint32_t component) {
  return gpu::signedUnit(gpu::randomBits(seed, static_cast<uint32_t>(serial),
                                         static_cast<uint32_t>(serial >> 32), component));
}

// The emitter's offset for this serial (docs/model.md, "Emission").
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

Reference::Reference(const Scene& scene) : scene_(scene) {
  bool lifetimes = false;
  for (const Emitter& e : scene.emitters) lifetimes = lifetimes || e.lifetime > 0.0f;
  modules_ = scene.integrator == Integrator::ExplicitEuler && scene.forces.empty() &&
                     scene.colliders.empty() && !lifetimes
                 ? Modules::Euler
                 : Modules::Any;
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    emitters_.push_back(emitterConstants(scene, k));
    lattices_.push_back(flowLattice(scene, k));
  }
  for (const Collider& c : scene.colliders) {
    normals_.push_back(c.type == ColliderType::Plane ? unitNormal(c.normal) : Vec3{});
    cones_.push_back(c.type == ColliderType::Cone ? coneConstants(c) : ConeConstants{});
  }
}

void Reference::emit(size_t emitter, uint64_t serial, Particle& q) const {
  const Emitter& e = scene_.emitters[emitter];
  if (lattices_[emitter].shape.x != gpu::kFillRandom) {  // at rest on its site
    const Vec3 x = latticePosition(lattices_[emitter], e.position, uint32_t(serial));
    q = {x.x, x.y, x.z, 0.0f, 0.0f, 0.0f, 0.0f, e.mass};
    return;
  }
  const uint32_t seed = scene_.seed + static_cast<uint32_t>(emitter);
  const V u{draw(seed, serial, 0), draw(seed, serial, 1), draw(seed, serial, 2)};
  const V x = Model::of(e.position) + offset(e, seed, serial);
  const V v = Model::flushed(V{e.velocity.x + e.spread.x * u.x, e.velocity.y + e.spread.y * u.y,
                        e.velocity.z + e.spread.z * u.z});
  q = {x.x, x.y, x.z, 0.0f, v.x, v.y, v.z, e.mass};
}

void Reference::step(size_t emitter, Particle& q) const {
  stepWith<Modules::Any>(emitter, q);
}

template <Modules Use>
void Reference::stepWith(size_t emitter, Particle& q) const {
  V x{q.px, q.py, q.pz}, v{q.vx, q.vy, q.vz};
  float age = q.age;
  Model::step<Use>(*this, emitter, x, v, age);
  q = {x.x, x.y, x.z, age, v.x, v.y, v.z, q.mass};
}

// Flattened: the step is inlined into the loop over the block, so the independent chains of
// neighbouring particles overlap in the CPU's pipeline.
template <Modules Use>
[[gnu::flatten]] void Reference::runWith(size_t emitter, const std::vector<Births>& schedule,
                                         uint32_t first, Particle* slots, size_t count) const {
  const uint32_t capacity = scene_.emitters[emitter].particles;
  for (const Births& b : schedule)
    for (size_t j = 0; j < count; ++j) {
      const uint32_t slot = first + static_cast<uint32_t>(j);
      const uint32_t rel = slot >= b.head ? slot - b.head : slot + capacity - b.head;
      if (rel < b.count) emit(emitter, b.firstSerial + rel, slots[j]);
      stepWith<Use>(emitter, slots[j]);
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
