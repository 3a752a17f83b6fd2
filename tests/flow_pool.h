// A pool of flow and the checks of how it behaves (docs/model.md, "The flow"), shared by the
// CPU reference's tests (flow_test.cpp) and lavapipe's (gpu_flow_test.cpp): each check takes
// a maker of the simulation under test.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "common/npy.h"
#include "lava/scene.h"
#include "lava/simulation.h"
#include "scene/keys.h"
#include "test_scenes.h"

namespace lava::test {

using MakeSimulation = std::function<std::unique_ptr<Simulation>(const Scene&)>;

// A scene of the explicit flow (flow.comp's on the GPU; the implicit flow's tests set its
// solver) and one flow emitter of `n` slots, all born in one burst at step 0 from `shape` at
// `position`: at rest, or scattered by `spread` (m/s).
inline Scene flowBurst(uint32_t n, Shape shape, Vec3 position, Vec3 spread = {}) {
  Scene s = oneEmitter(n, shape, position, {0.0f, 0.0f, 0.0f}, spread);
  s.flow.emplace();
  s.flow->solver = FlowSolver::Explicit;
  Emitter& e = s.emitters[0];
  e.rate = 0.0;
  e.burst = n;
  e.flow = true;
  e.mass = detail::defaultFlowMass(*s.flow);
  return s;
}

// A pool of `n` flow particles released at rest from a box above the ground at `x`, with
// no cooling unless a test asks for it.
inline Scene poolScene(uint32_t n, float x = 0.0f) {
  const float side = 0.5f * std::cbrt(float(n) * 2.7e-5f);  // n particles spaced 3 cm
  Scene s = flowBurst(n, Shape::Box, {x, side + 0.01f, 0.0f});
  s.flow->coolingAir = 0.0f;
  s.flow->coolingGround = 0.0f;
  s.emitters[0].size = {side, side, side};
  return s;
}

inline double kineticEnergy(const State& state) {
  double e = 0.0;
  for (const Particle& p : state.particles)
    if (!(p.age < 0.0f)) e += 0.5 * p.mass * (double(p.vx) * p.vx + double(p.vy) * p.vy +
                                              double(p.vz) * p.vz);
  return e;
}

// Kinetic energy and the potential energy of gravity above the ground, J.
inline double mechanicalEnergy(const State& state, float gravity) {
  double e = kineticEnergy(state);
  for (const Particle& p : state.particles)
    if (!(p.age < 0.0f)) e += double(p.mass) * gravity * p.py;
  return e;
}

// The horizontal distance from the pool's centre within which 90% of it lies.
inline double spread(const State& state) {
  double cx = 0.0, cz = 0.0;
  size_t n = 0;
  for (const Particle& p : state.particles)
    if (!(p.age < 0.0f)) cx += p.px, cz += p.pz, ++n;
  cx /= double(n), cz /= double(n);
  std::vector<double> r;
  for (const Particle& p : state.particles)
    if (!(p.age < 0.0f)) r.push_back(std::hypot(p.px - cx, p.pz - cz));
  std::sort(r.begin(), r.end());
  return r[r.size() * 9 / 10];
}

inline double meanX(const State& state) {
  double x = 0.0;
  for (const Particle& p : state.particles) x += p.px;
  return x / double(state.particles.size());
}

inline double medianNearest(const State& state) {
  std::vector<double> nearest;
  for (const Particle& a : state.particles) {
    double best = 1e30;
    for (const Particle& b : state.particles)
      if (&a != &b)
        best = std::min(best, std::hypot(double(a.px) - b.px, double(a.py) - b.py,
                                         double(a.pz) - b.pz));
    nearest.push_back(best);
  }
  std::sort(nearest.begin(), nearest.end());
  return nearest[nearest.size() / 2];
}

inline void expectSound(const State& state) {
  for (size_t i = 0; i < state.particles.size(); ++i) {
    const Particle& p = state.particles[i];
    for (float f : {p.px, p.py, p.pz, p.vx, p.vy, p.vz, p.age, state.temperature[i]})
      ASSERT_TRUE(std::isfinite(f)) << "slot " << i;
    ASSERT_GE(p.py, 0.0f) << "slot " << i << " is below the ground";
  }
}

// A pool released at rest spreads. Once its collapse is over, its energy (kinetic plus
// gravity's) falls at every look, a quarter second apart, until it stops: kinetic energy
// exactly 0, and 0 from then on. Returns the state at the end and its step count.
inline std::pair<State, uint64_t> expectPoolSpreadsAndSettles(const MakeSimulation& make,
                                                              uint32_t n = 500) {
  const Scene s = poolScene(n);
  const std::unique_ptr<Simulation> sim = make(s);
  sim->advance(50);
  uint64_t steps = 50;
  const double start = spread(sim->state());
  sim->advance(950);
  steps += 950;
  EXPECT_GT(spread(sim->state()), 1.5 * start) << "it spreads";
  double lastE = 0.0, lastM = mechanicalEnergy(sim->state(), s.gravity);
  uint64_t settled = 0;
  while (steps < 12000 && !settled) {
    sim->advance(250);
    steps += 250;
    const State now = sim->state();
    const double e = kineticEnergy(now), m = mechanicalEnergy(now, s.gravity);
    EXPECT_LT(m, lastM) << "after " << steps << " steps";
    if (e == 0.0) settled = steps;
    lastE = e;
    lastM = m;
  }
  EXPECT_NE(settled, 0u) << "the pool still moves after 12 s: " << lastE << " J";
  const State rest = sim->state();
  for (int k = 0; k < 20 && settled; ++k) {  // and never moves again
    sim->advance(50);
    steps += 50;
    EXPECT_EQ(kineticEnergy(sim->state()), 0.0) << steps - settled << " steps after it settled";
  }
  expectSound(rest);
  const double nearest = medianNearest(rest);
  EXPECT_GT(nearest, 0.25 * s.flow->radius);
  EXPECT_LT(nearest, s.flow->radius);
  return {sim->state(), steps};
}

inline double spreadAfter(const MakeSimulation& make, const Scene& s, uint64_t steps) {
  const std::unique_ptr<Simulation> sim = make(s);
  sim->advance(steps);
  const State state = sim->state();
  expectSound(state);
  return spread(state);
}

// A hotter pool, less viscous, runs further than a cooler one in the same second.
inline void expectHotterPoolRunsFurther(const MakeSimulation& make, uint32_t n = 500) {
  Scene hot = poolScene(n), cool = poolScene(n);
  hot.emitters[0].temperature = 1400.0f;
  cool.emitters[0].temperature = 1050.0f;  // above the solidus, far more viscous
  EXPECT_GT(spreadAfter(make, hot, 1000), 1.1 * spreadAfter(make, cool, 1000));
}

// On a plane tilted 20 degrees, falling towards +x (y = -tan(20 deg) x, above the ground
// where x < 0), a pool runs downhill once it has collapsed.
inline void expectPoolRunsDownhill(const MakeSimulation& make) {
  Scene s = poolScene(500, -1.5f);
  const float tilt = 20.0f * 3.14159265f / 180.0f;
  Collider plane;
  plane.type = ColliderType::Plane;
  plane.normal = {std::sin(tilt), std::cos(tilt), 0.0f};
  s.colliders.push_back(plane);
  s.emitters[0].position.y += 1.5f * std::tan(tilt);
  const std::unique_ptr<Simulation> sim = make(s);
  sim->advance(400);  // the collapse
  const double before = meanX(sim->state());
  sim->advance(1600);
  const State after = sim->state();
  expectSound(after);
  EXPECT_GT(meanX(after), before + 0.02) << "it runs downhill (+x)";
}

// A pool of viscosity 0.01 m^2/s spreads further in a second than one of 1.
inline void expectLessViscousPoolSpreadsFurther(const MakeSimulation& make) {
  Scene thin = poolScene(500), thick = poolScene(500);
  thin.flow->viscosity = 0.01f;
  thick.flow->viscosity = 1.0f;
  EXPECT_GT(spreadAfter(make, thin, 1000), 1.1 * spreadAfter(make, thick, 1000));
}

// A pool poured onto a sphere never has a particle inside it, nor below the ground.
inline void expectNoParticleInsideTheSphere(const MakeSimulation& make, uint32_t n = 500) {
  Scene s = poolScene(n);
  s.emitters[0].position.y += 0.5f;  // falls onto a sphere
  Collider ball;
  ball.type = ColliderType::Sphere;
  ball.position = {0.05f, 0.2f, 0.0f};
  ball.radius = 0.2f;
  s.colliders.push_back(ball);
  const std::unique_ptr<Simulation> sim = make(s);
  for (int k = 0; k < 10; ++k) {
    sim->advance(100);
    const State state = sim->state();
    expectSound(state);
    for (const Particle& p : state.particles) {
      const float dx = p.px - 0.05f, dy = p.py - 0.2f, dz = p.pz;
      ASSERT_GE(dx * dx + dy * dy + dz * dz, 0.2f * 0.2f * (1.0f - 1e-5f));
    }
  }
}

// The temperature column (docs/flow.md): an 8th column with the flow particles'
// temperatures, 0 for sparks and unborn slots; a scene without a flow keeps 7.
inline void expectTemperatureColumn(const MakeSimulation& make) {
  Scene s = poolScene(64);
  s.emitters.push_back(Emitter{});  // sparks
  s.emitters[1].particles = 100;
  s.emitters[1].rate = 20000.0;
  s.emitters[0].temperature = 1350.0f;
  s.emitters[0].particles = 80;  // 16 slots stay unborn
  const std::unique_ptr<Simulation> sim = make(s);
  sim->advance(3);
  const State state = sim->state();
  ASSERT_EQ(common::stateColumns(state), 8u);
  for (size_t i = 0; i < state.particles.size(); ++i) {
    float row[8];
    common::stateRow(state, i, row);
    if (i < 64)
      EXPECT_NEAR(row[7], 1350.0f, 1e-3f) << i;  // born at 1350 K, no cooling
    else
      EXPECT_EQ(row[7], 0.0f) << i << (i < 80 ? " (unborn)" : " (a spark)");
  }
  EXPECT_EQ(common::stateColumns(make(Scene{})->state()), 7u);
}

}  // namespace lava::test
