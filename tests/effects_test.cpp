// The modules of docs/model.md in the CPU reference, against closed forms and invariants: the
// integrators under constant gravity, bursts and lifetimes counted exactly, forces against
// hand-computed steps, colliders that leave nothing inside, the denormal rule.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "lava/simulation.h"
#include "sim/constants.h"
#include "sim/reference.h"
#include "test_scenes.h"

namespace lava {
namespace {

Scene oneParticle(Integrator integrator) {
  Scene s;
  s.integrator = integrator;
  Emitter& e = s.emitters[0];
  e.particles = 1;
  e.rate = 0.0;
  e.spread = {0.0f, 0.0f, 0.0f};
  e.radius = 0.0f;
  e.position = {0.0f, 50.0f, 0.0f};
  e.velocity = {1.0f, 8.0f, 0.0f};
  return s;
}

// Height and vertical velocity after `steps` steps of a particle launched at y0 with vy0.
std::pair<float, float> fall(const Scene& s, int steps) {
  Particle p{};
  detail::emitParticle(s, 0, 0, p);
  for (int k = 0; k < steps; ++k) detail::stepParticle(s, 0, p);
  return {p.py, p.vy};
}

TEST(Integrators, VelocityVerletFollowsTheParabolaToRounding) {
  // Under constant gravity Verlet is exact: what remains is float rounding, at most about
  // one ULP of |y| < 8 per step (two additions), ten times below explicit Euler's g h t / 2.
  Scene s = oneParticle(Integrator::VelocityVerlet);
  s.emitters[0].position.y = 1.0f;
  const double h = s.h(), g = s.gravity, ulp = std::ldexp(1.0, -21);  // ULP of floats in [4, 8)
  for (int steps : {1, 10, 500, 1500}) {
    const double t = steps * h;
    const auto [y, vy] = fall(s, steps);
    EXPECT_NEAR(y, 1.0 + 8.0 * t - 0.5 * g * t * t, steps * ulp) << steps;
    EXPECT_NEAR(vy, 8.0 - g * t, steps * ulp) << steps;
    EXPECT_LT(steps * ulp, 0.1 * 0.5 * g * h * t + 1e-5) << "the bound must tell Euler apart";
  }
}

TEST(Integrators, EulerVariantsMissTheParabolaByHalfGHT) {
  // Explicit Euler moves with the start-of-step velocity: y = parabola + g h t / 2; the
  // semi-implicit variant with the end-of-step one: y = parabola - g h t / 2.
  const Scene explicitEuler = oneParticle(Integrator::ExplicitEuler);
  const Scene semiImplicit = oneParticle(Integrator::SemiImplicitEuler);
  const double h = explicitEuler.h(), g = explicitEuler.gravity;
  for (int steps : {100, 1000, 1500}) {
    const double t = steps * h, parabola = 50.0 + 8.0 * t - 0.5 * g * t * t;
    EXPECT_NEAR(fall(explicitEuler, steps).first - parabola, 0.5 * g * h * t, 2e-4) << steps;
    EXPECT_NEAR(fall(semiImplicit, steps).first - parabola, -0.5 * g * h * t, 2e-4) << steps;
  }
}

TEST(Emission, BurstsAreExactAndPeriodic) {
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = 5000;
  e.rate = 0.0;
  e.burst = 100;
  e.burstInterval = 0.25;  // 250 steps of 1 ms: bursts at steps 0, 250, 500, 750
  CpuSimulation sim(s);
  sim.advance(249);
  EXPECT_EQ(sim.state().clocks[0].serial, 100u);
  sim.advance(1);  // step 249
  EXPECT_EQ(sim.state().clocks[0].serial, 100u);
  sim.advance(1);  // step 250
  EXPECT_EQ(sim.state().clocks[0].serial, 200u);
  sim.advance(749);  // to step 999
  EXPECT_EQ(sim.state().clocks[0].serial, 400u);
  e.burstInterval = 0.0;  // step 0 only, plus a fractional rate
  e.rate = 333.3;
  CpuSimulation once(s);
  once.advance(3000);
  EXPECT_EQ(once.state().clocks[0].serial, 100u + 999u);  // floor(3000 * 0.3333) = 999
}

TEST(Emission, LifetimesKillExactlyTheOldParticles) {
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = 4000;
  e.rate = 1000.0;  // one birth per step
  e.lifetime = 0.25f;
  const int steps = 1000;
  CpuSimulation sim(s);
  sim.advance(steps);
  // A particle born in step b is stepped in steps b .. steps-1, its age summed in float; it
  // is dead once that sum reached the lifetime.
  int expected = 0;
  for (int b = 0; b < steps; ++b) {
    float age = 0.0f;
    bool alive = true;
    for (int k = b; k < steps && alive; ++k) {
      age = age + s.h();
      alive = !(age >= e.lifetime);
    }
    expected += alive;
  }
  int alive = 0, dead = 0;
  for (const Particle& p : sim.state().particles) {
    alive += p.age >= 0.0f;
    dead += p.age == -1.0f && p.mass == e.mass;  // dead: age -1, x, v and m kept
  }
  EXPECT_EQ(alive, expected);
  EXPECT_EQ(alive + dead, steps);
  EXPECT_GT(dead, 700);
}

// One explicit Euler step of a particle at rest at x under one force, no gravity.
Particle stepUnder(const Force& force, float x, float y, float z) {
  Scene s = oneParticle(Integrator::ExplicitEuler);
  s.gravity = 0.0f;
  s.forces = {force};
  Particle p{x, y, z, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f};
  detail::stepParticle(s, 0, p);
  return p;
}

TEST(Forces, AttractorPullsTowardItsPointWithinItsRadius) {
  Force f;
  f.type = ForceType::Attractor;
  f.position = {1.0f, 2.0f, 3.0f};
  f.strength = 5.0f;
  f.radius = 2.0f;
  const float h = 0.001f;
  Particle p = stepUnder(f, 0.5f, 2.5f, 3.0f);  // d = p - x = (0.5, -0.5, 0): within 2 m
  EXPECT_EQ(p.px, 0.5f);                        // explicit Euler: x with the old v = 0
  EXPECT_EQ(p.vx, h * (5.0f * 0.5f));           // v = 0 + (h/m) k d
  EXPECT_EQ(p.vy, h * (5.0f * -0.5f));
  EXPECT_EQ(p.vz, 0.0f);
  p = stepUnder(f, 4.0f, 2.0f, 3.0f);  // 3 m away: outside the radius, no force
  EXPECT_EQ(p.vx, 0.0f);
  f.radius = 0.0f;  // radius 0: everywhere
  p = stepUnder(f, 4.0f, 2.0f, 3.0f);
  EXPECT_EQ(p.vx, h * (5.0f * -3.0f));
}

TEST(Forces, VortexTurnsAroundItsAxis) {
  Force f;
  f.type = ForceType::Vortex;
  f.position = {0.0f, 0.0f, 0.0f};
  f.axis = {0.0f, 2.0f, 0.0f};  // not normalised: the strength scales with it
  f.strength = 3.0f;
  const float h = 0.001f;
  // d = (1, 0, 0); axis x d = (a.y d.z - a.z d.y, a.z d.x - a.x d.z, a.x d.y - a.y d.x)
  //                        = (0, 0, -2): a turn about +y.
  const Particle p = stepUnder(f, 1.0f, 5.0f, 0.0f);
  EXPECT_EQ(p.vx, 0.0f);
  EXPECT_EQ(p.vy, 0.0f);
  EXPECT_EQ(p.vz, h * (3.0f * -2.0f));
}

// A fountain falling onto `collider` for 3 s.
State rainOn(const Collider& collider) {
  Scene s = test::oneEmitter(6000, Shape::Sphere, {0.0f, 3.0f, 0.0f}, {0.0f, 1.0f, 0.0f},
                             {1.0f, 1.0f, 1.0f});
  s.emitters[0].rate = 2000.0;
  s.emitters[0].radius = 0.3f;
  s.colliders = {collider};
  CpuSimulation sim(s, 2);
  sim.advance(3000);
  return sim.state();
}

TEST(Colliders, NothingEndsAStepInsideASphere) {
  Collider c;
  c.type = ColliderType::Sphere;
  c.position = {0.2f, 1.0f, 0.0f};
  c.radius = 0.6f;
  size_t resting = 0;
  for (const Particle& p : rainOn(c).particles) {
    if (p.age < 0.0f) continue;
    const double dx = p.px - 0.2, dy = p.py - 1.0, dz = p.pz;
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    ASSERT_GE(r, 0.6 * (1.0 - 1e-6)) << "inside at " << p.px << "," << p.py << "," << p.pz;
    resting += r < 0.61 && p.py > 1.0;
  }
  EXPECT_GT(resting, 10u) << "some lava must lie on the sphere";
}

TEST(Colliders, NothingEndsAStepInsideABox) {
  Collider c;
  c.type = ColliderType::Box;
  c.position = {0.0f, 1.0f, 0.0f};
  c.size = {0.5f, 0.4f, 0.6f};
  size_t onTop = 0;
  for (const Particle& p : rainOn(c).particles) {
    if (p.age < 0.0f) continue;
    const double d[3] = {std::fabs(p.px - 0.0), std::fabs(p.py - 1.0), std::fabs(p.pz - 0.0)};
    const double e[3] = {0.5, 0.4, 0.6};
    bool inside = true;
    for (int i = 0; i < 3; ++i) inside = inside && d[i] < e[i] * (1.0 - 1e-6);
    ASSERT_FALSE(inside) << "inside at " << p.px << "," << p.py << "," << p.pz;
    onTop += std::fabs(p.py - 1.4) < 1e-3;
  }
  EXPECT_GT(onTop, 10u) << "some lava must rest on the box";
}

TEST(Colliders, NothingEndsAStepInsideTheCone) {
  Collider c = test::cone(1.5f, 0.3f, 1.2f);
  c.friction = 0.95f;
  size_t onSlope = 0;
  for (const Particle& p : rainOn(c).particles) {
    if (p.age < 0.0f) continue;
    // README's definition, in double: inside when 0 <= y < H and r < R(y).
    const double y = p.py, r = std::sqrt(double(p.px) * p.px + double(p.pz) * p.pz);
    const double ry = 1.5 + (0.3 - 1.5) * y / 1.2;
    ASSERT_FALSE(y >= 0.0 && y < 1.2 && r < ry) << "inside at r " << r << ", y " << y;
    onSlope += y > 0.05 && y < 1.15 && r < ry + 0.01;
  }
  EXPECT_GT(onSlope, 50u) << "lava must lie on the slope";
}

// Particles on a box's top, within 3 cm above it.
size_t onTheBoxes(const Scene& s, const State& state) {
  size_t n = 0;
  for (const Particle& p : state.particles)
    for (const Collider& c : s.colliders)
      n += p.age >= 0.0f && std::fabs(p.px - c.position.x) < c.size.x &&
           std::fabs(p.pz - c.position.z) < c.size.z && p.py >= c.position.y + c.size.y &&
           p.py < c.position.y + c.size.y + 0.03f;
  return n;
}

TEST(Colliders, NothingEndsAStepInsideABoxStandingOnTheGroundSunkOrInACorner) {
  // Flow and sparks, every step (docs/model.md "Contact").
  const Scene s = test::boxesOnTheGround();
  CpuSimulation sim(s, 2);
  for (int step = 1; step <= 1200; ++step) {
    sim.advance(1);
    ASSERT_EQ(test::insideTheGroundOrTheBoxes(s, sim.state()), "") << "after step " << step;
  }
  EXPECT_GT(onTheBoxes(s, sim.state()), 40u) << "flow and sparks must lie on the boxes";
}

// One particle without gravity, stepped 10 ms at a time, and two boxes (centre, half-extents).
Scene betweenTwoBoxes(const Vec3& ca, const Vec3& ea, const Vec3& cb, const Vec3& eb) {
  Scene s = oneParticle(Integrator::ExplicitEuler);
  s.gravity = 0.0f;
  s.dt = 0.01;
  Collider a;
  a.type = ColliderType::Box;
  a.position = ca;
  a.size = ea;
  Collider b = a;
  b.position = cb;
  b.size = eb;
  s.colliders = {a, b};
  return s;
}

TEST(Colliders, AParticleThatRoundsOfContactCannotFreeTakesBackItsStartOrDies) {
  // Two tall boxes overlapping from x = -0.1 to 0.1: in the overlap, each one's nearest face
  // lies inside the other, and the rounds of contact ping-pong between them.
  Scene s = betweenTwoBoxes({-0.4f, 2.0f, 0.0f}, {0.5f, 1.5f, 1.5f}, {0.4f, 2.0f, 0.0f},
                            {0.5f, 1.5f, 1.5f});
  // Thrown from x = 1 (outside) into the overlap in one step: back to x = 1, at rest.
  Particle p{1.0f, 2.0f, 0.0f, 0.5f, -95.0f, 0.0f, 0.0f, 1.0f};
  detail::stepParticle(s, 0, p);
  EXPECT_EQ(p.px, 1.0f);
  EXPECT_EQ(p.vx, 0.0f);
  EXPECT_FLOAT_EQ(p.age, 0.51f);
  // Starting in the overlap (born there, or a box moved over it): it dies, x = v = 0.
  p = Particle{0.05f, 2.0f, 0.0f, 0.5f, 0.0f, 0.0f, 0.0f, 1.0f};
  detail::stepParticle(s, 0, p);
  EXPECT_EQ(p.age, -1.0f);
  EXPECT_EQ(p.px, 0.0f);
  EXPECT_EQ(p.py, 0.0f);
  // One box alone frees it: out through its nearer face, as docs/model.md's box rule says.
  s.colliders = {s.colliders[1]};
  p = Particle{0.05f, 2.0f, 0.0f, 0.5f, 0.0f, 0.0f, 0.0f, 1.0f};
  detail::stepParticle(s, 0, p);
  EXPECT_EQ(p.px, 0.4f - 0.5f);
  EXPECT_GE(p.age, 0.0f);
}

TEST(Colliders, AParticlePutOutOnABoxFaceIsOutsideItInAContainersCorner) {
  // Two walls of a container meeting at a vertical edge: a's inner face at x = 0.17 - 0.05,
  // b's at z = 0.17 - 0.05. |x - centre| of a particle put on a face can round to just
  // below the size (here 0.049999997): a box found it inside again, the two put it out in
  // turn for every round, and a particle that had rested on a face (its start inside by
  // that test) died there. 272 of a water block's 512 did in 2 s at a frame's step.
  Scene s = betweenTwoBoxes({0.17f, 0.3f, 0.0f}, {0.05f, 0.3f, 0.3f}, {0.0f, 0.3f, 0.17f},
                            {0.3f, 0.3f, 0.05f});
  const float face = 0.17f - 0.05f;
  // On a's face, thrown into the corner: put out on both faces, alive, and bounces off them.
  Particle p{face, 0.1f, 0.1f, 0.5f, 1.0f, 0.0f, 3.0f, 1.0f};
  detail::stepParticle(s, 0, p);
  EXPECT_GE(p.age, 0.0f);
  EXPECT_EQ(p.px, face);
  EXPECT_EQ(p.pz, face);
  EXPECT_LT(p.vx, 0.0f);
  EXPECT_LT(p.vz, 0.0f);
}

TEST(Colliders, PlaneBouncesWithItsOwnRestitution) {
  // A wall x = 0 facing +x: a particle moving at -2 m/s through it comes back at +1 m/s.
  Scene s = oneParticle(Integrator::ExplicitEuler);
  s.gravity = 0.0f;
  Collider wall;
  wall.type = ColliderType::Plane;
  wall.normal = {3.0f, 0.0f, 0.0f};  // any length
  wall.restitution = 0.5f;
  wall.friction = 1.0f;
  s.colliders = {wall};
  Particle p{0.001f, 1.0f, 0.0f, 0.0f, -2.0f, 0.0f, 0.5f, 1.0f};
  detail::stepParticle(s, 0, p);
  EXPECT_EQ(p.px, 0.0f);  // projected onto the plane
  EXPECT_EQ(p.vx, 1.0f);  // -(0.5 * -2)
  EXPECT_EQ(p.vz, 0.5f);  // tangential, kept whole
}

TEST(Denormals, NoVelocityComponentBetweenZeroAnd2ToTheMinus24) {
  // A scene where, without the flush rule, 891 CPU velocities were denormal by step 2000.
  Scene s;
  s.gravity = 0.0f;
  s.drag = 5.0f;
  s.dt = 0.01;
  s.emitters[0].velocity = {1.0f, 1.0f, 1.0f};
  s.emitters[0].rate = 100.0;
  CpuSimulation sim(s);
  sim.advance(2000);
  size_t zeroed = 0;
  for (const Particle& p : sim.state().particles)
    for (float v : {p.vx, p.vy, p.vz}) {
      ASSERT_FALSE(v != 0.0f && std::fabs(v) < 5.9604644775390625e-8f) << v;
      ASSERT_FALSE(std::signbit(v) && v == 0.0f) << "-0 must become +0";
      zeroed += v == 0.0f;
    }
  EXPECT_GT(zeroed, 1000u);  // drag brought most of them to rest
}

}  // namespace
}  // namespace lava
