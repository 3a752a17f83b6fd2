#include "scene_params.h"

#include "constants.h"

namespace lava::detail {
namespace {

glm::vec4 v4(const Vec3& v, float w) {
  return {v.x, v.y, v.z, w};
}

}  // namespace

gpu::SceneParams sceneParams(const Scene& s) {
  gpu::SceneParams p{};
  p.world = {s.h(), s.restitution, s.friction, s.drag};
  p.wind = v4(s.wind, 0.0f);
  uint32_t first = 0;
  for (size_t k = 0; k < s.emitters.size(); ++k) {
    const Emitter& e = s.emitters[k];
    const EmitterConstants c = emitterConstants(s, k);
    gpu::EmitterParams& g = p.emitters[k];
    g.position = v4(e.position, e.radius);
    g.velocity = v4(e.velocity, e.mass);
    g.spread = v4(e.spread, e.lifetime);
    g.size = v4(e.size, c.hm);
    g.constants = {c.hh, c.hk, c.w, 0.0f};
    g.ring = {uint32_t(e.shape), s.seed + uint32_t(k), e.particles, first};
    first += e.particles;
  }
  for (size_t i = 0; i < s.forces.size(); ++i) {
    const Force& f = s.forces[i];
    gpu::ForceParams& g = p.forces[i];
    g.position = v4(f.position, f.strength);
    g.axis = v4(f.axis, f.radius * f.radius);
    g.kind = {uint32_t(f.type), f.radius == 0.0f ? 1u : 0u, 0u, 0u};
  }
  for (size_t i = 0; i < s.colliders.size(); ++i) {
    const Collider& c = s.colliders[i];
    gpu::ColliderParams& g = p.colliders[i];
    g.position = v4(c.position, 0.0f);
    g.material = {c.restitution, c.friction, 0.0f, 0.0f};
    g.kind = {uint32_t(c.type), 0u, 0u, 0u};
    switch (c.type) {
      case ColliderType::Plane:
        g.shape = v4(unitNormal(c.normal), 0.0f);
        break;
      case ColliderType::Sphere:
        g.shape = {c.radius, c.radius * c.radius, 0.0f, 0.0f};
        break;
      case ColliderType::Box:
        g.shape = v4(c.size, 0.0f);
        break;
      case ColliderType::Cone: {
        const ConeConstants k = coneConstants(c);
        g.shape = {c.baseRadius, k.slope, c.height, 0.0f};
        g.cone = {k.radial, k.vertical, k.capY, k.margin};
        break;
      }
    }
  }
  return p;
}

Constants stepConstants(const Scene& s) {
  uint32_t lifetimes = 0;
  for (const Emitter& e : s.emitters) lifetimes |= e.lifetime > 0.0f ? 1u : 0u;
  uint32_t forceKinds = 0, colliderKinds = 0;
  for (size_t i = 0; i < s.forces.size(); ++i)
    forceKinds |= (s.forces[i].type == ForceType::Vortex ? 1u : 0u) << i;
  for (size_t i = 0; i < s.colliders.size(); ++i)
    colliderKinds |= uint32_t(s.colliders[i].type) << (2 * i);
  return {gpu::kWorkgroupSize,       uint32_t(s.integrator),       uint32_t(s.emitters.size()),
          uint32_t(s.forces.size()), uint32_t(s.colliders.size()), lifetimes,
          forceKinds,                colliderKinds};
}

}  // namespace lava::detail
