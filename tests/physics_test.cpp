// The CPU reference against closed forms (docs/model.md): explicit Euler before the first
// bounce, the ground impulse (restitution, retention, rest threshold), forces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include "lava/simulation.h"
#include "sim/reference.h"

namespace lava {
namespace {

using detail::emitParticle;

Scene singleParticleScene() {
  Scene s;
  s.emitters[0].particles = 1;
  s.emitters[0].rate = 0.0;
  s.emitters[0].spread = {0.0f, 0.0f, 0.0f};
  s.emitters[0].radius = 0.0f;
  return s;
}

Particle alive(Vec3 x, Vec3 v, float age = 1.0f, float mass = 1.0f) {
  return Particle{x.x, x.y, x.z, age, v.x, v.y, v.z, mass};
}

void stepParticle(const Scene& s, Particle& p) {
  detail::stepParticle(s, 0, p);
}

TEST(Physics, EulerMatchesClosedFormBeforeFirstBounce) {
  Scene s = singleParticleScene();
  s.emitters[0].position = {0.5f, 2.0f, -0.25f};
  s.emitters[0].velocity = {1.0f, 5.0f, -2.0f};
  const double h = s.h(), g = s.gravity;
  Particle p{};
  emitParticle(s, 0, 0, p);
  stepParticle(s, p);  // born and integrated in step 1
  for (int k = 1; k <= 900; ++k) {
    // x_k = x0 + k h v0 - g h^2 k (k-1) / 2 ; v_k = v0 - k h g  (explicit Euler, exactly)
    const double y = 2.0 + k * h * 5.0 - g * h * h * k * (k - 1) / 2.0;
    ASSERT_GT(y, 0.0) << "the test must end before the bounce";
    EXPECT_NEAR(p.px, 0.5 + k * h * 1.0, 1e-4) << "step " << k;  // float rounding
    EXPECT_NEAR(p.py, y, 1e-4) << "step " << k;
    EXPECT_NEAR(p.pz, -0.25 - k * h * 2.0, 1e-4) << "step " << k;
    EXPECT_NEAR(p.vy, 5.0 - k * h * g, 1e-4) << "step " << k;
    EXPECT_FLOAT_EQ(p.vx, 1.0f);
    EXPECT_NEAR(p.age, k * h, 1e-6 * k);  // float sum of k steps
    stepParticle(s, p);
  }
}

TEST(Physics, PositionUsesStartOfStepVelocity) {
  Scene s = singleParticleScene();
  Particle p = alive({0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
  stepParticle(s, p);
  EXPECT_EQ(p.py, 1.0f);  // v was 0 at the start of the step
  EXPECT_EQ(p.vy, -s.h() * s.gravity);
}

TEST(Physics, BounceAppliesRestitutionAndRetention) {
  Scene s = singleParticleScene();
  s.restitution = 0.5f;
  s.friction = 0.25f;
  Particle p = alive({0.0f, 0.001f, 0.0f}, {2.0f, -4.0f, -1.0f});
  stepParticle(s, p);
  const float vy = -4.0f - s.h() * s.gravity;  // pre-impact velocity after the Euler step
  EXPECT_EQ(p.py, 0.0f);
  EXPECT_EQ(p.vy, -(0.5f * vy));
  EXPECT_EQ(p.vx, 0.25f * 2.0f);
  EXPECT_EQ(p.vz, 0.25f * -1.0f);
  EXPECT_EQ(p.px, 0.0f + s.h() * 2.0f);
}

TEST(Physics, RestThresholdZeroesSlowTangentialVelocity) {
  Scene s = singleParticleScene();
  s.friction = 0.5f;
  Particle p = alive({0.0f, 0.0f, 0.0f}, {1.9e-4f, -1.0f, -2.2e-4f});
  stepParticle(s, p);
  EXPECT_EQ(p.vx, 0.0f);             // 0.95e-4 < 1e-4: static friction
  EXPECT_EQ(p.vz, 0.5f * -2.2e-4f);  // 1.1e-4 stays
  EXPECT_FALSE(std::signbit(p.vx));
}

TEST(Physics, NoImpulseWhenRisingThroughTheGround) {
  Scene s = singleParticleScene();
  s.gravity = 0.0f;
  Particle p = alive({0.0f, -0.5f, 0.0f}, {3.0f, 1.0f, 0.0f});
  stepParticle(s, p);
  EXPECT_EQ(p.py, 0.0f);  // clamped to the ground
  EXPECT_EQ(p.vy, 1.0f);  // already leaving: no restitution
  EXPECT_EQ(p.vx, 3.0f);  // and no damping
}

TEST(Physics, ElasticBounceKeepsSpeedAndZeroRestitutionStops) {
  Scene s = singleParticleScene();
  s.restitution = 1.0f;
  Particle p = alive({0.0f, 0.0f, 0.0f}, {0.0f, -3.0f, 0.0f});
  stepParticle(s, p);
  EXPECT_EQ(p.vy, 3.0f + s.h() * s.gravity);
  s.restitution = 0.0f;
  p = alive({0.0f, 0.0f, 0.0f}, {0.0f, -3.0f, 0.0f});
  stepParticle(s, p);
  EXPECT_EQ(p.vy, 0.0f);
}

TEST(Physics, DragAndWindReachTerminalVelocity) {
  Scene s = singleParticleScene();
  s.drag = 2.0f;
  s.emitters[0].mass = 0.5f;
  s.wind = {1.0f, 0.0f, -0.5f};
  s.dt = 0.002;
  Particle p = alive({0.0f, 1e4f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, s.emitters[0].mass);
  for (int k = 0; k < 20000; ++k) stepParticle(s, p);
  // m dv/dt = wind - m g y - k v = 0  ->  v = (wind - m g y) / k
  EXPECT_NEAR(p.vx, 1.0 / 2.0, 1e-4);
  EXPECT_NEAR(p.vy, -0.5 * 9.81 / 2.0, 1e-4);
  EXPECT_NEAR(p.vz, -0.5 / 2.0, 1e-4);
}

TEST(Physics, HeavierParticlesFallAlikeWithoutDrag) {
  Scene light = singleParticleScene(), heavy = light;
  heavy.emitters[0].mass = 8.0f;
  Particle a = alive({0.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, light.emitters[0].mass);
  Particle b = alive({0.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, heavy.emitters[0].mass);
  for (int k = 0; k < 500; ++k) {
    stepParticle(light, a);
    stepParticle(heavy, b);
  }
  EXPECT_NEAR(a.vy, b.vy, 1e-5);
}

TEST(Physics, SceneStaysAboveGroundAndStateIsAFunctionOfAge) {
  Scene s;
  s.emitters[0].particles = 3000;
  s.emitters[0].spread = {0.0f, 0.0f, 0.0f};
  s.emitters[0].radius = 0.0f;
  CpuSimulation sim(s);
  sim.advance(6000);
  std::map<float, Particle> byAge;
  size_t alive = 0;
  for (const Particle& p : sim.state().particles) {
    if (p.age < 0.0f) continue;
    ++alive;
    EXPECT_GE(p.py, 0.0f);
    auto [it, inserted] = byAge.emplace(p.age, p);
    if (!inserted) {
      EXPECT_EQ(0, std::memcmp(&it->second, &p, sizeof(Particle)));
    }
  }
  EXPECT_EQ(alive, s.particles());
}

TEST(Physics, EmissionStaysInTheDiscAndVelocitySpread) {
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = 20000;
  e.burst = 20000;  // the whole ring in step 1
  s.gravity = 0.0f;
  s.dt = 1e-6;
  CpuSimulation sim(s);
  sim.advance(1);
  double mean[3] = {0.0, 0.0, 0.0};
  const float velocity[3] = {e.velocity.x, e.velocity.y, e.velocity.z};
  const float spread[3] = {e.spread.x, e.spread.y, e.spread.z};
  for (const Particle& p : sim.state().particles) {
    const float dx = p.px - e.position.x, dz = p.pz - e.position.z;
    EXPECT_LE(std::sqrt(dx * dx + dz * dz), e.radius * 1.0001f);
    const float v[3] = {p.vx, p.vy, p.vz};
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(std::fabs(v[c] - velocity[c]), spread[c] * 1.0001f);
      mean[c] += v[c];
    }
  }
  EXPECT_NEAR(mean[0] / e.particles, e.velocity.x, 0.03);
  EXPECT_NEAR(mean[1] / e.particles, e.velocity.y, 0.03);
}

}  // namespace
}  // namespace lava
