// Scenes the tests share: each module of docs/model.md on its own and all together, and random
// scenes drawing every module.
#pragma once
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "lava/scene.h"

namespace lava::test {

// The names moduleScene() knows, for parameterised tests.
inline constexpr const char* kModules[] = {
    "point",      "disc",           "sphere",       "box",  "attractor",           "vortex",
    "plane",      "sphere-collider", "box-collider", "cone", "semi-implicit-euler",
    "velocity-verlet", "bursts-lifetimes", "all"};

// "sphere-collider" -> "sphere_collider" (test names take no '-').
inline std::string moduleTestName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

// Every module of docs/model.md on its own, and all of them together: 20,000+ particles over
// 3,000 steps, bit-identical on the GPU and the CPU reference.
inline Scene moduleScene(const std::string& module) {
  Scene s;
  s.seed = 777;
  Emitter& e = s.emitters[0];
  e.particles = 20000;
  e.rate = 9000.0;
  e.spread = {1.5f, 1.5f, 1.5f};
  e.position = {0.0f, 1.0f, 0.0f};
  const auto add = [&s](Collider c) { s.colliders.push_back(c); };
  if (module == "point") e.shape = Shape::Point;
  if (module == "sphere") e.shape = Shape::Sphere, e.radius = 0.4f;
  if (module == "box") e.shape = Shape::Box, e.size = {0.5f, 0.2f, 0.3f};
  if (module == "semi-implicit-euler") s.integrator = Integrator::SemiImplicitEuler;
  if (module == "velocity-verlet") s.integrator = Integrator::VelocityVerlet;
  if (module == "bursts-lifetimes") e.burst = 3000, e.burstInterval = 0.3, e.lifetime = 0.7f;
  if (module == "attractor" || module == "all")
    s.forces.push_back({ForceType::Attractor, {0.5f, 2.0f, 0.0f}, {}, 8.0f, 1.5f});
  if (module == "vortex" || module == "all")
    s.forces.push_back({ForceType::Vortex, {0.0f, 0.0f, 0.0f}, {0.0f, 1.5f, 0.2f}, 2.0f, 0.0f});
  Collider c;
  c.restitution = 0.6f;
  c.friction = 0.8f;
  if (module == "plane" || module == "all") {
    c.type = ColliderType::Plane;
    c.position = {0.0f, 0.0f, -1.0f};
    c.normal = {0.0f, 0.3f, 1.0f};
    add(c);
  }
  if (module == "sphere-collider" || module == "all") {
    c.type = ColliderType::Sphere;
    c.position = {0.3f, 2.5f, 0.0f};
    c.radius = 0.5f;
    add(c);
  }
  if (module == "box-collider" || module == "all") {
    c.type = ColliderType::Box;
    c.position = {-0.8f, 0.4f, 0.2f};
    c.size = {0.4f, 0.4f, 0.5f};
    add(c);
  }
  if (module == "cone" || module == "all") {
    c.type = ColliderType::Cone;
    c.position = {0.0f, 0.0f, 0.0f};
    c.baseRadius = 1.6f;
    c.topRadius = 0.25f;
    c.height = 0.9f;
    add(c);
  }
  if (module == "all") {
    s.integrator = Integrator::VelocityVerlet;
    s.drag = 0.1f;
    s.wind = {0.4f, 0.0f, -0.3f};
    e.lifetime = 1.5f;
    const Emitter first = e;  // `e` dangles once the list grows
    Emitter second = first;
    second.particles = 7000;
    second.shape = Shape::Sphere;
    second.position = {1.0f, 3.0f, 0.5f};
    second.mass = 0.4f;
    second.burst = 500;
    second.burstInterval = 0.2;
    s.emitters.push_back(second);
    Emitter third = first;
    third.particles = 3000;
    third.shape = Shape::Box;
    third.size = {0.2f, 0.1f, 0.2f};
    third.lifetime = 0.0f;
    s.emitters.push_back(third);
  }
  return s;
}

// A random scene: any integrator, emitter shapes, bursts and lifetimes, 0-3 forces and
// 0-4 colliders of any kind, with random parameters (valid ones).
inline Scene randomModuleScene(std::mt19937& rng) {
  auto uniform = [&](float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(rng);
  };
  auto pick = [&](uint32_t n) { return static_cast<uint32_t>(rng() % n); };
  auto vec = [&](float lo, float hi) { return Vec3{uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; };
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
