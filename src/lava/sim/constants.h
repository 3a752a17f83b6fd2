// The host constants of docs/model.md: computed once from the scene in float32 (the plane
// normal and the cone's constants in double, then float32), the same for both backends.
#pragma once
#include "lava/scene.h"

namespace lava::detail {

struct EmitterConstants {
  float hm;  // h / m
  float hh;  // (0.5 h) hm
  float hk;  // 0.5 hm
  float w;   // wind.y - m g
};
EmitterConstants emitterConstants(const Scene& scene, size_t emitter);

// The plane's normal scaled to unit length (in double, then float32).
Vec3 unitNormal(const Vec3& normal);

// The solid truncated cone of README "The crater".
struct ConeConstants {
  float slope;     // (top radius - base radius) / height: the radius shrinks by this per m up
  float radial;    // the side's outward unit normal: its part along the radial direction
  float vertical;  // and its part along +y
  float capY;      // y of the top cap, a margin above the cone (m)
  float margin;    // how far beyond the surface a particle is pushed out (m)
};
ConeConstants coneConstants(const Collider& cone);

}  // namespace lava::detail
