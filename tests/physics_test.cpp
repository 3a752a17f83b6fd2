// The CPU reference against closed forms of SPEC §2: explicit Euler before the first
// bounce, the ground impulse (restitution, retention, rest threshold), forces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include "cpu_simulator.h"

namespace lava {
namespace {

Scene singleParticleScene() {
  Scene s;
  s.particles = 1;
  s.rate = 0.0;
  s.spread = {0.0f, 0.0f, 0.0f};
  s.emitterRadius = 0.0f;
  return s;
}

Particle alive(glm::vec3 x, glm::vec3 v, float age = 1.0f, float mass = 1.0f) {
  return Particle{glm::vec4(x, age), glm::vec4(v, mass)};
}

TEST(Physics, EulerMatchesClosedFormBeforeFirstBounce) {
  Scene s = singleParticleScene();
  s.emitter = {0.5f, 2.0f, -0.25f};
  s.velocity = {1.0f, 5.0f, -2.0f};
  const double h = s.dt, g = s.gravity;
  Particle p{};
  p.posAge.w = -1.0f;
  stepParticle(s, p, true, 0);  // born and integrated in step 1
  for (int k = 1; k <= 900; ++k) {
    // x_k = x0 + k h v0 - g h^2 k (k-1) / 2 ; v_k = v0 - k h g  (explicit Euler, exactly)
    const double y = 2.0 + k * h * 5.0 - g * h * h * k * (k - 1) / 2.0;
    ASSERT_GT(y, 0.0) << "the test must end before the bounce";
    EXPECT_NEAR(p.posAge.x, 0.5 + k * h * 1.0, 1e-4) << "step " << k;  // float rounding
    EXPECT_NEAR(p.posAge.y, y, 1e-4) << "step " << k;
    EXPECT_NEAR(p.posAge.z, -0.25 - k * h * 2.0, 1e-4) << "step " << k;
    EXPECT_NEAR(p.velMass.y, 5.0 - k * h * g, 1e-4) << "step " << k;
    EXPECT_FLOAT_EQ(p.velMass.x, 1.0f);
    EXPECT_NEAR(p.posAge.w, k * h, 1e-6 * k);  // float sum of k steps
    stepParticle(s, p, false, 0);
  }
}

TEST(Physics, PositionUsesStartOfStepVelocity) {
  Scene s = singleParticleScene();
  Particle p = alive({0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
  stepParticle(s, p, false, 0);
  EXPECT_EQ(p.posAge.y, 1.0f);  // v was 0 at the start of the step
  EXPECT_EQ(p.velMass.y, -s.dt * s.gravity);
}

TEST(Physics, BounceAppliesRestitutionAndRetention) {
  Scene s = singleParticleScene();
  s.restitution = 0.5f;
  s.friction = 0.25f;
  Particle p = alive({0.0f, 0.001f, 0.0f}, {2.0f, -4.0f, -1.0f});
  stepParticle(s, p, false, 0);
  const float vy = -4.0f - s.dt * s.gravity;  // pre-impact velocity after the Euler step
  EXPECT_EQ(p.posAge.y, 0.0f);
  EXPECT_EQ(p.velMass.y, -(0.5f * vy));
  EXPECT_EQ(p.velMass.x, 0.25f * 2.0f);
  EXPECT_EQ(p.velMass.z, 0.25f * -1.0f);
  EXPECT_EQ(p.posAge.x, 0.0f + s.dt * 2.0f);
}

TEST(Physics, RestThresholdZeroesSlowTangentialVelocity) {
  Scene s = singleParticleScene();
  s.friction = 0.5f;
  Particle p = alive({0.0f, 0.0f, 0.0f}, {1.9e-4f, -1.0f, -2.2e-4f});
  stepParticle(s, p, false, 0);
  EXPECT_EQ(p.velMass.x, 0.0f);             // 0.95e-4 < 1e-4: static friction
  EXPECT_EQ(p.velMass.z, 0.5f * -2.2e-4f);  // 1.1e-4 stays
  EXPECT_FALSE(std::signbit(p.velMass.x));
}

TEST(Physics, NoImpulseWhenRisingThroughTheGround) {
  Scene s = singleParticleScene();
  s.gravity = 0.0f;
  Particle p = alive({0.0f, -0.5f, 0.0f}, {3.0f, 1.0f, 0.0f});
  stepParticle(s, p, false, 0);
  EXPECT_EQ(p.posAge.y, 0.0f);   // clamped to the ground
  EXPECT_EQ(p.velMass.y, 1.0f);  // already leaving: no restitution
  EXPECT_EQ(p.velMass.x, 3.0f);  // and no damping
}

TEST(Physics, ElasticBounceKeepsSpeedAndZeroRestitutionStops) {
  Scene s = singleParticleScene();
  s.restitution = 1.0f;
  Particle p = alive({0.0f, 0.0f, 0.0f}, {0.0f, -3.0f, 0.0f});
  stepParticle(s, p, false, 0);
  EXPECT_EQ(p.velMass.y, 3.0f + s.dt * s.gravity);
  s.restitution = 0.0f;
  p = alive({0.0f, 0.0f, 0.0f}, {0.0f, -3.0f, 0.0f});
  stepParticle(s, p, false, 0);
  EXPECT_EQ(p.velMass.y, 0.0f);
}

TEST(Physics, DragAndWindReachTerminalVelocity) {
  Scene s = singleParticleScene();
  s.drag = 2.0f;
  s.mass = 0.5f;
  s.wind = {1.0f, 0.0f, -0.5f};
  s.dt = 0.002f;
  Particle p = alive({0.0f, 1e4f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, s.mass);
  for (int k = 0; k < 20000; ++k) stepParticle(s, p, false, 0);
  // m dv/dt = wind - m g y - k v = 0  ->  v = (wind - m g y) / k
  EXPECT_NEAR(p.velMass.x, 1.0 / 2.0, 1e-4);
  EXPECT_NEAR(p.velMass.y, -0.5 * 9.81 / 2.0, 1e-4);
  EXPECT_NEAR(p.velMass.z, -0.5 / 2.0, 1e-4);
}

TEST(Physics, HeavierParticlesFallAlikeWithoutDrag) {
  Scene light = singleParticleScene(), heavy = light;
  heavy.mass = 8.0f;
  Particle a = alive({0.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, light.mass);
  Particle b = alive({0.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, heavy.mass);
  for (int k = 0; k < 500; ++k) {
    stepParticle(light, a, false, 0);
    stepParticle(heavy, b, false, 0);
  }
  EXPECT_NEAR(a.velMass.y, b.velMass.y, 1e-5);
}

TEST(Physics, SceneStaysAboveGroundAndStateIsAFunctionOfAge) {
  Scene s;
  s.particles = 3000;
  s.spread = {0.0f, 0.0f, 0.0f};
  s.emitterRadius = 0.0f;
  CpuSimulator sim(s);
  sim.advance(6000);
  std::map<float, Particle> byAge;
  size_t alive = 0;
  for (const Particle& p : sim.state().particles) {
    if (p.posAge.w < 0.0f) continue;
    ++alive;
    EXPECT_GE(p.posAge.y, 0.0f);
    auto [it, inserted] = byAge.emplace(p.posAge.w, p);
    if (!inserted) {
      EXPECT_EQ(0, std::memcmp(&it->second, &p, sizeof(Particle)));
    }
  }
  EXPECT_EQ(alive, s.particles);
}

TEST(Physics, EmissionStaysInTheDiscAndVelocitySpread) {
  Scene s;
  s.particles = 20000;
  s.rate = 4e10;  // 40000 owed, capped at 20000: the whole ring in step 1
  s.gravity = 0.0f;
  s.dt = 1e-6f;
  CpuSimulator sim(s);
  sim.advance(1);
  glm::dvec3 mean(0.0);
  for (const Particle& p : sim.state().particles) {
    const float dx = p.posAge.x - s.emitter.x, dz = p.posAge.z - s.emitter.z;
    EXPECT_LE(std::sqrt(dx * dx + dz * dz), s.emitterRadius * 1.0001f);
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(std::fabs(p.velMass[c] - s.velocity[c]), s.spread[c] * 1.0001f);
    mean += glm::dvec3(p.velMass);
  }
  mean /= double(s.particles);
  EXPECT_NEAR(mean.x, s.velocity.x, 0.03);
  EXPECT_NEAR(mean.y, s.velocity.y, 0.03);
}

}  // namespace
}  // namespace lava
