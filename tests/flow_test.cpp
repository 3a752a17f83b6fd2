// The flow (docs/model.md, "The flow") on the CPU: its scene keys, its state and columns, and
// how a pool of it behaves: it spreads and settles, runs downhill, runs further hot than
// cool, crusts over, never gains energy, and stays above the ground and out of colliders.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/npy.h"
#include "lava/checkpoint.h"
#include "lava/error.h"
#include "lava/scene.h"
#include "lava/simulation.h"
#include "scene/keys.h"
#include "flow_pool.h"
#include "sim/flow.h"

namespace lava {
namespace {

using test::expectSound;
using test::meanX;
using test::poolScene;

std::unique_ptr<Simulation> cpuReference(const Scene& s) {
  return std::make_unique<CpuSimulation>(s, 1);
}

TEST(FlowKeys, TheTableAndTheEmitterKeysReadBack) {
  const Scene s = parseScene(R"(
[[emitter]]
flow = true
temperature = 1300
[[emitter]]
particles = 10
[flow]
radius = 0.05
viscosity-solidus = 7
conduction = 1e-3
)",
                             "flow.toml");
  ASSERT_TRUE(s.flow);
  EXPECT_EQ(s.flow->radius, 0.05f);
  EXPECT_EQ(s.flow->viscositySolidus, 7.0f);
  EXPECT_EQ(s.flow->temperature, 1400.0f);  // the default
  EXPECT_TRUE(s.emitters[0].flow);
  EXPECT_FALSE(s.emitters[1].flow);
  EXPECT_EQ(s.emitters[0].temperature, 1300.0f);
  // A flow emitter without `mass`: particles spaced half the radius apart; others keep 1 kg.
  EXPECT_EQ(s.emitters[0].mass, detail::defaultFlowMass(*s.flow));
  EXPECT_NEAR(s.emitters[0].mass, 2600.0 * 0.025 * 0.025 * 0.025, 1e-6);
  EXPECT_EQ(s.emitters[1].mass, 1.0f);
  EXPECT_EQ(toToml(parseScene(toToml(s), "again")), toToml(s));
}

TEST(FlowKeys, AFlowEmitterWithoutTheTableGetsTheDefaults) {
  const Scene s = parseScene("[[emitter]]\nflow = true\n", "f.toml");
  ASSERT_TRUE(s.flow);
  EXPECT_EQ(s.flow->radius, 0.06f);
  EXPECT_EQ(s.emitters[0].mass, detail::defaultFlowMass(*s.flow));
}

TEST(FlowKeys, ScenesWithoutAFlowWriteWhatTheyWroteBefore) {
  const std::string text = toToml(Scene{});
  EXPECT_EQ(text.find("flow"), std::string::npos) << text;
  EXPECT_EQ(text.find("temperature"), std::string::npos) << text;
  EXPECT_FALSE(parseScene(text, "t").flow);
}

std::string errorOf(const std::string& toml) {
  try {
    parseScene(toml, "f.toml");
    checkScene(parseScene(toml, "f.toml"));
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(FlowKeys, BadValuesNameTheKeyAndWhatIsAccepted) {
  EXPECT_NE(errorOf("[[emitter]]\nflow = 1\n").find("flow: expected true or false"),
            std::string::npos);
  EXPECT_NE(errorOf("[flow]\nradius = -1\n").find("flow.radius"), std::string::npos);
  EXPECT_NE(errorOf("[flow]\nsolidus = 1500\n").find("flow.solidus: expected below"),
            std::string::npos);
  EXPECT_NE(errorOf("[flow]\nviscosity = 9\n").find("flow.viscosity-solidus: expected at least"),
            std::string::npos);
  EXPECT_NE(errorOf("[flow]\nviscosty = 9\n").find("did you mean viscosity?"), std::string::npos);
  EXPECT_NE(errorOf("flow = 3\n").find("flow"), std::string::npos);
  // 1 kg at 2600 kg/m^3 is 7 cm across, wider than the radius's 3/4.
  const std::string mass = errorOf("[[emitter]]\nflow = true\nmass = 1\n");
  EXPECT_NE(mass.find("emitter[0].mass: a flow particle of 1 kg"), std::string::npos) << mass;
  EXPECT_NE(errorOf("dt = 0.01\n[flow]\ncooling-air = 60\ncooling-ground = 50\n")
                .find("flow.cooling-ground"),
            std::string::npos);
  Scene code;
  code.emitters[0].flow = true;  // without Scene::flow
  EXPECT_THROW(checkScene(code), InvalidArgument);
}

TEST(FlowKeys, ViscosityIsExactAtBothEndsAndMonotoneBetween) {
  Scene s = poolScene(8);
  s.flow->viscosity = 0.05f;
  s.flow->viscositySolidus = 5.0f;
  const detail::FlowConstants k = detail::flowConstants(s);
  EXPECT_EQ(detail::flowViscosity(k, 1400.0f), 0.05f);
  EXPECT_EQ(detail::flowViscosity(k, 2000.0f), 0.05f);
  EXPECT_EQ(detail::flowViscosity(k, 1000.0f), 5.0f);
  float last = 5.0f;
  for (float t = 1000.0f; t <= 1400.0f; t += 0.37f) {
    const float nu = detail::flowViscosity(k, t);
    ASSERT_LE(nu, last) << t << " K";
    last = nu;
  }
}

TEST(FlowState, TheTemperatureColumnHoldsFlowParticlesOnly) {
  test::expectTemperatureColumn(cpuReference);
}

TEST(FlowState, ACheckpointResumesTheFlowBitForBit) {
  Scene s = poolScene(300);
  s.flow->coolingAir = 5.0f;  // crust forms within the run
  CpuSimulation straight(s, 1);
  straight.advance(400);
  CpuSimulation first(s, 1);
  first.advance(200);
  const Snapshot saved = parseCheckpoint(checkpointBytes(s, first.state()), "test");
  CpuSimulation second(saved.scene, 2);
  second.setState(saved.state);
  second.advance(200);
  const State a = straight.state(), b = second.state();
  EXPECT_EQ(0, std::memcmp(a.particles.data(), b.particles.data(),
                           a.particles.size() * sizeof(Particle)));
  EXPECT_EQ(a.temperature, b.temperature);
  EXPECT_EQ(a.crust, b.crust);
}

TEST(FlowState, ThreadCountsGiveTheSameBytes) {
  const Scene s = poolScene(3000);  // past the size at which the flow's passes split
  CpuSimulation one(s, 1), two(s, 2), three(s, 3);
  for (CpuSimulation* sim : {&one, &two, &three}) sim->advance(150);
  const State a = one.state(), b = two.state(), c = three.state();
  EXPECT_EQ(stateHash(a.particles), stateHash(b.particles));
  EXPECT_EQ(stateHash(a.particles), stateHash(c.particles));
  EXPECT_EQ(a.temperature, c.temperature);
}

TEST(FlowState, TheSimdKernelGivesTheReferenceBytes) {
  Scene s = poolScene(300);
  s.emitters.push_back(Emitter{});
  s.emitters[1].particles = 500;
  CpuSimulation scalar(s, 1), simd(s, 2, CpuKernel::Simd);
  scalar.advance(300);
  simd.advance(300);
  const State a = scalar.state(), b = simd.state();
  EXPECT_EQ(stateHash(a.particles), stateHash(b.particles));
  EXPECT_EQ(a.temperature, b.temperature);
}

TEST(FlowPhysics, APoolReleasedAtRestSpreadsSettlesAndNeverGainsEnergy) {
  test::expectPoolSpreadsAndSettles(cpuReference);
}

TEST(FlowPhysics, OnAPlaneTiltedTwentyDegreesThePoolRunsDownhill) {
  // The plane falls towards +x: y = -tan(20 deg) x, above the ground where x < 0.
  Scene s = poolScene(500, -1.5f);
  const float tilt = 20.0f * 3.14159265f / 180.0f;
  Collider plane;
  plane.type = ColliderType::Plane;
  plane.normal = {std::sin(tilt), std::cos(tilt), 0.0f};
  s.colliders.push_back(plane);
  s.emitters[0].position.y += 1.5f * std::tan(tilt);
  CpuSimulation cpu(s, 1);
  cpu.advance(400);  // the collapse
  const double before = meanX(cpu.state());
  cpu.advance(1600);
  const State after = cpu.state();
  expectSound(after);
  EXPECT_GT(meanX(after), before + 0.02) << "it runs downhill (+x)";
}

TEST(FlowPhysics, TheLessViscousPoolSpreadsFurther) {
  Scene thin = poolScene(500), thick = poolScene(500);
  thin.flow->viscosity = 0.01f;
  thick.flow->viscosity = 1.0f;
  EXPECT_GT(test::spreadAfter(cpuReference, thin, 1000),
            1.1 * test::spreadAfter(cpuReference, thick, 1000));
}

TEST(FlowPhysics, AHotterPoolRunsFurtherThanACoolerOne) {
  test::expectHotterPoolRunsFurther(cpuReference);
}

TEST(FlowPhysics, CrustStopsExactlyAndNeverMovesAgain) {
  Scene s = poolScene(500);
  s.flow->coolingAir = 4.0f;  // from 1400 K to the solidus in about 0.4 s
  s.flow->coolingGround = 4.0f;
  CpuSimulation cpu(s, 1);
  cpu.advance(1000);
  const State a = cpu.state();
  size_t crust = 0;
  for (size_t i = 0; i < a.particles.size(); ++i)
    if (a.crust[i]) {
      ++crust;
      EXPECT_LE(a.temperature[i], s.flow->solidus);
      EXPECT_TRUE(a.particles[i].vx == 0.0f && a.particles[i].vy == 0.0f &&
                  a.particles[i].vz == 0.0f)
          << "slot " << i;
    }
  EXPECT_GT(crust, a.particles.size() / 2) << "most of the pool has crusted";
  cpu.advance(500);
  const State b = cpu.state();
  for (size_t i = 0; i < a.particles.size(); ++i)
    if (a.crust[i]) {
      ASSERT_TRUE(b.crust[i]);
      EXPECT_EQ(a.particles[i].px, b.particles[i].px);
      EXPECT_EQ(a.particles[i].py, b.particles[i].py);
      EXPECT_EQ(a.particles[i].pz, b.particles[i].pz);
      EXPECT_EQ(b.particles[i].vy, 0.0f);
    }
}

TEST(FlowPhysics, NoParticleEndsInsideACollider) {
  test::expectNoParticleInsideTheSphere(cpuReference);
}

}  // namespace
}  // namespace lava
