// Scenes the tests share: each module of docs/model.md on its own and all together, and random
// scenes drawing every module.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "lava/scene.h"
#include "lava/state.h"
#include "module_scenes.h"
#include "scene/keys.h"

namespace lava::test {

// A scene of one emitter of `n` slots, born (at the default rate) from `shape` at `position`
// and launched at `velocity` give or take `spread` in each component (m/s).
inline Scene oneEmitter(uint32_t n, Shape shape, Vec3 position, Vec3 velocity, Vec3 spread) {
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = n;
  e.shape = shape;
  e.position = position;
  e.velocity = velocity;
  e.spread = spread;
  return s;
}

// A cone collider standing on the ground at the origin.
inline Collider cone(float baseRadius, float topRadius, float height) {
  Collider c;
  c.type = ColliderType::Cone;
  c.position = {0.0f, 0.0f, 0.0f};
  c.baseRadius = baseRadius;
  c.topRadius = topRadius;
  c.height = height;
  return c;
}

// The volcano's cone at the origin (the look and embedding tests hide lava behind it).
inline Scene coneScene() {
  Scene scene;
  scene.colliders = {cone(1.6f, 0.4f, 1.4f)};
  return scene;
}

// Boxes as walls, steps and crates stand (docs/model.md "Contact"): one standing on the
// ground, one sunk 10 cm into it, and two whose ends overlap in a corner; a flow poured onto
// them and sparks raining on all four. 600 flow particles and 2,000 sparks.
inline Scene boxesOnTheGround() {
  Scene s;
  s.flow.emplace();
  s.flow->coolingAir = 0.0f;
  s.flow->coolingGround = 0.0f;
  s.friction = 0.3f;
  auto box = [&](Vec3 centre, Vec3 half) {
    Collider c;
    c.type = ColliderType::Box;
    c.position = centre;
    c.size = half;
    c.friction = 0.3f;
    s.colliders.push_back(c);
  };
  box({0.45f, 0.12f, -0.3f}, {0.12f, 0.12f, 0.3f});   // standing
  box({-0.45f, 0.02f, -0.3f}, {0.12f, 0.12f, 0.3f});  // sunk
  box({0.0f, 0.1f, 0.45f}, {0.5f, 0.1f, 0.06f});      // the corner's two ends overlap
  box({0.45f, 0.1f, 0.25f}, {0.06f, 0.1f, 0.25f});
  Emitter& flow = s.emitters[0];
  flow.flow = true;
  flow.particles = 600;
  flow.rate = 3000.0;
  flow.shape = Shape::Disc;
  flow.radius = 0.1f;
  flow.position = {0.3f, 0.5f, 0.2f};
  flow.velocity = {0.6f, -1.0f, 0.4f};
  flow.spread = {0.3f, 0.1f, 0.3f};
  flow.mass = detail::defaultFlowMass(*s.flow);
  Emitter sparks;
  sparks.particles = 2000;
  sparks.rate = 4000.0;
  sparks.shape = Shape::Box;
  sparks.size = {0.6f, 0.05f, 0.6f};
  sparks.position = {0.0f, 0.9f, 0.0f};
  sparks.velocity = {0.0f, -1.0f, 0.0f};
  sparks.spread = {0.8f, 0.5f, 0.8f};
  s.emitters.push_back(sparks);
  return s;
}

// Whether p lies inside the ground or one of s's boxes, strictly between its faces c -+ e
// in float32 as the model has it: a box standing on the ground (its bottom at or below it)
// holds from the ground up.
inline bool insideTheGroundOrABox(const Scene& s, const Particle& p) {
  if (p.py < 0.0f) return true;
  for (const Collider& c : s.colliders) {
    if (c.type != ColliderType::Box) continue;
    const Vec3 lo{c.position.x - c.size.x, c.position.y - c.size.y, c.position.z - c.size.z};
    const Vec3 hi{c.position.x + c.size.x, c.position.y + c.size.y, c.position.z + c.size.z};
    const bool standing = double(c.position.y) - c.size.y <= 0.0;
    if (lo.x < p.px && p.px < hi.x && lo.z < p.pz && p.pz < hi.z && p.py < hi.y &&
        (standing || lo.y < p.py))
      return true;
  }
  return false;
}

// The alive particles of `state` inside the ground or a box, with the first one's place.
inline std::string insideTheGroundOrTheBoxes(const Scene& s, const State& state) {
  size_t inside = 0;
  std::string first;
  for (size_t i = 0; i < state.particles.size(); ++i) {
    const Particle& p = state.particles[i];
    if (p.age < 0.0f || !insideTheGroundOrABox(s, p)) continue;
    if (inside++ == 0)
      first = " (slot " + std::to_string(i) + " at " + std::to_string(p.px) + ", " +
              std::to_string(p.py) + ", " + std::to_string(p.pz) + ")";
  }
  return inside == 0 ? "" : std::to_string(inside) + " inside" + first;
}

// The module scenes (scenes/modules/*.toml: each module of docs/model.md on its own and all
// of them together, 20,000+ particles), the ones the builtin suite runs too: their names, for
// parameterised tests.
inline const std::vector<const char*>& moduleNames() {
  static const std::vector<const char*> names = [] {
    std::vector<const char*> out;
    for (const scenes::ModuleScene& m : scenes::kModuleScenes) out.push_back(m.name);
    return out;
  }();
  return names;
}

// "collider-sphere" -> "collider_sphere" (test names take no '-').
inline std::string moduleTestName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

inline Scene moduleScene(const std::string& name) {
  for (const scenes::ModuleScene& m : scenes::kModuleScenes)
    if (name == m.name) return parseScene(m.toml, "scenes/modules/" + name + ".toml");
  throw std::invalid_argument("no module scene '" + name + "'");
}

// A random scene: any integrator, emitter shapes, bursts and lifetimes, 0-3 forces and
// 0-4 colliders of any kind, with random parameters (valid ones).
inline Scene randomModuleScene(std::mt19937& rng) {
  auto uniform = [&](float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(rng);
  };
  auto pick = [&](uint32_t n) { return static_cast<uint32_t>(rng() % n); };
  auto vec = [&](float lo, float hi) {
    return Vec3{uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)};
  };
  Scene s;
  s.seed = static_cast<uint32_t>(rng());
  s.dt = uniform(0.0005f, 0.004f);
  s.gravity = uniform(1.0f, 20.0f);
  s.restitution = uniform(0.0f, 1.0f);
  s.friction = uniform(0.0f, 1.0f);
  s.wind = vec(-1, 1);
  s.drag = pick(2) ? uniform(0.01f, 0.5f) : 0.0f;
  s.integrator = static_cast<Integrator>(pick(3));
  s.emitters.clear();
  for (uint32_t k = 0, n = 1 + pick(3); k < n; ++k) {
    Emitter e;
    e.particles = 1000 + pick(3000);
    e.rate = uniform(500.0f, 20000.0f);
    e.shape = static_cast<Shape>(pick(4));
    e.position = {uniform(-1, 1), uniform(0.2f, 3), uniform(-1, 1)};
    e.radius = uniform(0.01f, 1.0f);
    e.size = vec(0.01f, 0.5f);
    e.velocity = {uniform(-2, 2), uniform(0, 8), uniform(-2, 2)};
    e.spread = vec(0.01f, 3);
    e.mass = uniform(0.1f, 5.0f);
    if (pick(2)) e.burst = pick(2000), e.burstInterval = pick(2) ? uniform(0.05f, 0.5f) : 0.0;
    if (pick(2)) e.lifetime = uniform(0.1f, 2.0f);
    s.emitters.push_back(e);
  }
  for (uint32_t i = 0, n = pick(4); i < n; ++i) {
    Force f;
    f.type = static_cast<ForceType>(pick(2));
    f.position = vec(-1, 2);
    f.axis = vec(-1, 1);
    f.strength = uniform(0.1f, 10.0f);
    f.radius = pick(2) ? uniform(0.1f, 2.0f) : 0.0f;
    s.forces.push_back(f);
  }
  for (uint32_t i = 0, n = pick(5); i < n; ++i) {
    Collider c;
    c.type = static_cast<ColliderType>(pick(4));
    c.position = {uniform(-1, 1), uniform(0, 2), uniform(-1, 1)};
    c.normal = {uniform(-1, 1), uniform(0.1f, 1), uniform(-1, 1)};
    c.radius = uniform(0.1f, 1.0f);
    c.size = vec(0.1f, 0.8f);
    c.baseRadius = uniform(0.3f, 1.5f);
    c.topRadius = uniform(0.0f, c.baseRadius);
    c.height = uniform(0.1f, 1.5f);
    c.restitution = uniform(0.0f, 1.0f);
    c.friction = uniform(0.0f, 1.0f);
    s.colliders.push_back(c);
  }
  return s;
}

}  // namespace lava::test
