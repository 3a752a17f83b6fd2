// The flow on the Vulkan backend (shaders/flow.comp) against the CPU reference on lavapipe:
// the same bits for the particles, temperatures and crust flags, across chunks and live edits;
// the sparks beside a flow untouched; the pool's physics checks on lavapipe itself. The module
// scene "flow" runs in the Modules tests too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "expect_throw.h"
#include "flow/gpu_flow.h"
#include "flow_pool.h"
#include "lava/lava.h"
#include "lava/validation.h"
#include "scene/keys.h"
#include "test_scenes.h"
#include "vulkan/device_context.h"
#include "vulkan_test.h"

namespace lava {
namespace {

using GpuFlow = test::VulkanTest;

void expectSameState(const Scene& s, const State& gpu, const State& cpu) {
  const Comparison c = compare(s, gpu, cpu);
  EXPECT_EQ(c.equal, c.particles) << "first difference at slot "
                                  << (c.first ? c.first->particle : 0) << " ("
                                  << (c.first ? fieldName(c.first->field) : "") << ")";
  EXPECT_EQ(stateHash(gpu), stateHash(cpu));
}

uint64_t crusted(const State& state) {
  uint64_t n = 0;
  for (uint8_t c : state.crust) n += c;
  return n;
}

// A pool released at rest onto a plane tilted 20 degrees: every particle born at once, many
// to a cell, and a collider that is not the ground.
Scene tiltedPool() {
  Scene s = test::flowBurst(700, Shape::Box, {0.0f, 0.5f, 0.0f});
  s.flow->coolingGround = 2.0f;
  s.flow->temperature = 1100.0f;
  s.emitters[0].size = {0.12f, 0.08f, 0.12f};
  s.emitters[0].mass = 0.06f;
  Collider plane;
  plane.type = ColliderType::Plane;
  plane.position = {0.0f, 0.3f, 0.0f};
  plane.normal = {0.34202f, 0.93969f, 0.0f};  // 20 degrees
  s.colliders.push_back(plane);
  return s;
}

// Lattice fills of a box, a sphere and a disc (flow.comp's integer site search against
// flow/lattice.cpp's): the same bits at birth and after they fall and spread.
TEST_F(GpuFlow, LatticeFillsAreBitIdenticalToTheCpu) {
  Scene s;
  s.flow.emplace();
  s.emitters.clear();
  const Shape shapes[3] = {Shape::Box, Shape::Sphere, Shape::Disc};
  const uint32_t bursts[3] = {200, 123, 37};
  for (int k = 0; k < 3; ++k) {
    Emitter e;
    e.flow = true;
    e.fill = Fill::Lattice;
    e.rate = 0.0;
    e.shape = shapes[k];
    e.burst = bursts[k];
    e.particles = 256;
    e.mass = 0.0208f;  // 2 cm apart
    e.radius = 0.07f;
    e.size = {0.09f, 0.05f, 0.07f};
    e.position = {0.3f * float(k) - 0.3f, 0.2f + 0.05f * float(k), 0.1f};
    s.emitters.push_back(e);
  }
  checkScene(s);
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  for (const uint64_t steps : {1, 299}) {
    gpu.advance(steps);
    cpu.advance(steps);
    expectSameState(s, gpu.state(), cpu.state());
  }
}

TEST_F(GpuFlow, AReleasedPoolOnATiltedPlaneIsBitIdenticalToTheCpu) {
  // On lavapipe: the pool lands on the plane, runs downhill (+x), cools into crust that stays
  // exactly still, never goes below the plane; and every bit is the CPU's.
  const Scene s = tiltedPool();
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  double meanX = 0.0;
  State before;
  for (int round = 0; round < 3; ++round) {
    gpu.advance(400);
    cpu.advance(400);
    const State now = gpu.state();
    expectSameState(s, now, cpu.state());
    double x = 0.0;
    for (size_t i = 0; i < now.particles.size(); ++i) {
      const Particle& p = now.particles[i];
      x += p.px;
      const float above = 0.34202f * p.px + 0.93969f * (p.py - 0.3f);  // along the normal
      EXPECT_GE(above, -1e-5f) << "slot " << i << " below the plane";
      if (now.crust[i]) {
        EXPECT_TRUE(p.vx == 0.0f && p.vy == 0.0f && p.vz == 0.0f) << "crust moves: " << i;
        if (!before.crust.empty() && before.crust[i]) {
          EXPECT_TRUE(p.px == before.particles[i].px && p.py == before.particles[i].py &&
                      p.pz == before.particles[i].pz)
              << "crust " << i << " moved";
        }
      }
    }
    x /= double(now.particles.size());
    if (round > 0) {
      EXPECT_GT(x, meanX) << "the pool runs downhill, towards +x";
    }
    meanX = x;
    before = now;
  }
  EXPECT_GT(crusted(before), 0u);  // it cooled on the plane into crust
}

// The CPU reference's pool checks (flow_pool.h, FlowPhysics.*) on lavapipe itself, with pools
// of 216 rather than 500: lavapipe takes about 10 us a particle-step on them.
constexpr uint32_t kPool = 216;

TEST_F(GpuFlow, APoolReleasedAtRestSpreadsSettlesAndNeverGainsEnergy) {
  const auto [settled, steps] = test::expectPoolSpreadsAndSettles(
      [&](const Scene& s) { return std::make_unique<GpuSimulation>(device(), s); }, kPool);
  const Scene s = test::poolScene(kPool);
  CpuSimulation cpu(s, 2);
  cpu.advance(steps);
  expectSameState(s, settled, cpu.state());
}

TEST_F(GpuFlow, AHotterPoolRunsFurtherThanACoolerOne) {
  test::expectHotterPoolRunsFurther(
      [&](const Scene& s) { return std::make_unique<GpuSimulation>(device(), s); }, kPool);
}

TEST_F(GpuFlow, TheTemperatureColumnHoldsFlowParticlesOnly) {
  test::expectTemperatureColumn(
      [&](const Scene& s) { return std::make_unique<GpuSimulation>(device(), s); });
}

TEST_F(GpuFlow, NoParticleEndsInsideACollider) {
  test::expectNoParticleInsideTheSphere(
      [&](const Scene& s) { return std::make_unique<GpuSimulation>(device(), s); }, kPool);
}

TEST_F(GpuFlow, BoxesStandingSunkOrInACornerHoldFlowAndSparksBitForBit) {
  // docs/model.md "Contact" on lavapipe against the CPU reference and its SIMD twin: no
  // particle inside the ground or a box every 10 steps, the same bits every 300.
  const Scene s = test::boxesOnTheGround();
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2), simd(s, 2, CpuKernel::Simd);
  for (int step = 10; step <= 1200; step += 10) {
    gpu.advance(10);
    const State g = gpu.state();
    ASSERT_EQ(test::insideTheGroundOrTheBoxes(s, g), "") << "after step " << step;
    if (step % 300 != 0) continue;
    cpu.advance(300);
    simd.advance(300);
    expectSameState(s, g, cpu.state());
    expectSameState(s, simd.state(), cpu.state());
  }
}

TEST_F(GpuFlow, APointBurstPastTheBucketCapIsBitIdenticalToTheCpu) {
  // 3,000 flow particles born at one point: one bucket holds them all, far past the 64 the
  // neighbour loops read (docs/model.md "Neighbours, bounded"), so the GPU's order pass
  // keeps the 64 lowest from the scatter's order and the rest read themselves after them.
  const Scene s = test::flowBurst(3000, Shape::Point, {0.0f, 0.5f, 0.0f}, {0.5f, 0.5f, 0.5f});
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  for (uint64_t steps : {1u, 1u, 8u, 40u}) {
    gpu.advance(steps);
    cpu.advance(steps);
    expectSameState(s, gpu.state(), cpu.state());
  }
}

TEST_F(GpuFlow, NonFiniteValuesDieTheSameOnBothBackends) {
  // A host sets NaN and infinite positions and velocities into flow particles and sparks:
  // after a step each of them is dead with x = v = 0 (docs/model.md "Non-finite values"),
  // the others untouched by them, and the GPU holds the CPU's bits.
  const Scene s = test::boxesOnTheGround();
  CpuSimulation cpu(s, 2);
  cpu.advance(150);
  State poked = cpu.state();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<std::pair<size_t, int>> pokes = {{3, 0},   {40, 1},  {77, 2},  {150, 3},
                                                     {600, 0}, {650, 1}, {700, 2}, {800, 3}};
  for (const auto& [slot, how] : pokes) {
    Particle& p = poked.particles[slot];
    ASSERT_GE(p.age, 0.0f) << slot;
    if (how == 0) p.px = nan;
    if (how == 1) p.vy = -nan;
    if (how == 2) p.pz = inf;
    if (how == 3) p.vx = -inf;
  }
  GpuSimulation gpu(device(), s);
  gpu.setState(poked);
  cpu.setState(poked);
  gpu.advance(1);
  cpu.advance(1);
  const State g = gpu.state(), c = cpu.state();
  expectSameState(s, g, c);
  EXPECT_EQ(
      std::memcmp(g.particles.data(), c.particles.data(), g.particles.size() * sizeof(Particle)),
      0);
  size_t alive = 0;
  for (size_t i = 0; i < g.particles.size(); ++i) {
    const Particle& p = g.particles[i];
    const bool wasPoked =
        std::any_of(pokes.begin(), pokes.end(), [&](const auto& k) { return k.first == i; });
    if (wasPoked) {
      EXPECT_EQ(p.age, -1.0f) << i;
      EXPECT_EQ(std::vector<float>({p.px, p.py, p.pz, p.vx, p.vy, p.vz}),
                std::vector<float>(6, 0.0f))
          << i;
      if (i < 600) {
        EXPECT_EQ(g.temperature[i], 0.0f) << i;
      }
      continue;
    }
    for (float f : {p.px, p.py, p.pz, p.vx, p.vy, p.vz}) ASSERT_TRUE(std::isfinite(f)) << i;
    alive += p.age >= 0.0f;
  }
  EXPECT_GT(alive, 500u);
  // The step goes on as before: 150 more steps agree too.
  gpu.advance(150);
  cpu.advance(150);
  expectSameState(s, gpu.state(), cpu.state());
}

TEST_F(GpuFlow, FlowSlotsAcrossChunksAndLiveEditsStayBitIdentical) {
  Scene s = test::moduleScene("flow");
  GpuSimulationOptions options;
  options.maxParticlesPerChunk = 1024;  // each flow emitter's ring across chunk boundaries
  GpuSimulation gpu(device(), s, options);
  ASSERT_GT(gpu.chunks().size(), 3u);
  CpuSimulation cpu(s, 3);
  for (int edit = 0; edit < 3; ++edit) {
    gpu.advance(350);
    cpu.advance(350);
    expectSameState(s, gpu.state(), cpu.state());
    // The panel's live edits of the flow's keys.
    s.flow->viscosity = 0.05f * float(edit + 2);
    s.flow->coolingAir = 0.1f * float(edit + 1);
    s.flow->conduction = 0.0f;
    s.emitters[1].temperature = 1200.0f - 20.0f * float(edit);
    gpu.setScene(s);
    cpu.setScene(s);
  }
  gpu.advance(350);
  cpu.advance(350);
  expectSameState(s, gpu.state(), cpu.state());
  EXPECT_GT(crusted(cpu.state()), 0u);
}

TEST_F(GpuFlow, AGridOfManyRunsIsBitIdenticalToTheCpu) {
  // 70,000 slots: 262,144 buckets in 8,192 runs in 256 blocks, 4 to each of the scan's
  // invocations; 3,000 particles born in a ball, each with a few dozen neighbours.
  Scene s = test::oneEmitter(70000, Shape::Sphere, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f},
                             {0.1f, 0.1f, 0.1f});
  s.flow.emplace();
  Emitter& e = s.emitters[0];
  e.rate = 200000.0;
  e.radius = 0.25f;
  e.flow = true;
  e.mass = 0.06f;
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  gpu.advance(15);
  cpu.advance(15);
  expectSameState(s, gpu.state(), cpu.state());
}

TEST_F(GpuFlow, SparksBesideAFlowAreUntouched) {
  // The module scene's sparks (emitter 0) with and without the flow emitters after them: the
  // same bytes in their slots.
  const Scene withFlow = test::moduleScene("flow");
  Scene without = withFlow;
  without.flow.reset();
  for (Emitter& e : without.emitters) {
    e.flow = false;
    e.temperature = 0.0f;
  }
  GpuSimulation a(device(), withFlow), b(device(), without);
  a.advance(800);
  b.advance(800);
  const State sa = a.state(), sb = b.state();
  const uint32_t sparks = withFlow.emitters[0].particles;
  EXPECT_EQ(std::memcmp(sa.particles.data(), sb.particles.data(), sparks * sizeof(Particle)), 0);
  for (uint32_t i = 0; i < sparks; ++i) ASSERT_EQ(sa.temperature[i], 0.0f) << i;
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

TEST_F(GpuFlow, SlotCountsAreCheckedBeforeTheyAreNarrowed) {
  // Three flow emitters of 2^31 - 1 slots each: 6,442,450,941 slots, which 32 bits would
  // have read as 2,147,483,645. The flow is refused by its true size before any buffer.
  Scene s;
  s.flow.emplace();
  s.emitters.resize(3);
  for (Emitter& e : s.emitters) {
    e.particles = 0x7fffffffu;
    e.flow = true;
    e.mass = detail::defaultFlowMass(*s.flow);
  }
  const auto makeFlow = [&] { detail::GpuFlow flow(device().context(), s); };
  const auto wide = test::expectThrowsWith<InvalidArgument>(makeFlow, "reach slot 6442450941");
  if (wide) {
    EXPECT_EQ(wide->parameter(), "particles");
  }
  s.emitters.resize(2);  // 4,294,967,294 slots: within 32 bits, past any binding
  test::expectThrowsWith<InvalidArgument>(makeFlow, "the flow's 4294967294 slots need a ");
}

TEST_F(GpuFlow, AFlowBeyondOneBindingIsRefusedUpFront) {
  // The flow's per-slot results are one binding (48 bytes a slot): a flow past the device's
  // binding range is refused when the simulation is made, naming the particles and the limit.
  const auto& c = device().context();
  const uint64_t range = std::min<uint64_t>(c.limits.maxStorageBufferRange, c.maxAllocation);
  Scene s;
  s.flow.emplace();
  Emitter& e = s.emitters[0];
  e.particles = static_cast<uint32_t>(range / 48 + 64);
  e.flow = true;
  e.mass = s.flow->density * 0.03f * 0.03f * 0.03f;
  const auto error = test::expectThrowsWith<InvalidArgument>(
      [&] { GpuSimulation gpu(device(), s); },
      "the flow's " + std::to_string(e.particles) + " slots need a ",
      std::to_string(e.particles) + " flow slots were accepted");
  if (error) {
    EXPECT_EQ(error->parameter(), "particles");
  }
}

// The implicit flow has no shader yet: the GPU backend steps it on the host with the CPU
// backends' code as the steps are recorded. Its bits are theirs across chunks, live edits, a
// resume, and frames a host records (update, recordSimulate) as well as blocking steps.
TEST_F(GpuFlow, TheImplicitFlowIsSteppedOnTheHostWithTheCpusBits) {
  Scene s = test::moduleScene("flow");
  s.flow->solver = FlowSolver::Implicit;
  s.dt = 1.0f / 120.0f;
  GpuSimulationOptions options;
  options.maxParticlesPerChunk = 1024;  // each flow emitter's ring across chunk boundaries
  GpuSimulation gpu(device(), s, options);
  ASSERT_GT(gpu.chunks().size(), 3u);
  ASSERT_NE(gpu.flowBuffers().particles, VK_NULL_HANDLE);
  CpuSimulation cpu(s, 3);
  for (int edit = 0; edit < 2; ++edit) {
    gpu.advance(90);
    cpu.advance(90);
    expectSameState(s, gpu.state(), cpu.state());
    s.flow->viscosity = 0.5f * float(edit + 1);  // the panel's live edits
    s.emitters[1].temperature = 1200.0f - 20.0f * float(edit);
    gpu.setScene(s);
    cpu.setScene(s);
  }
  for (uint32_t frame = 0; frame < 12; ++frame) {  // a host's frames, 0 to 11 steps each
    const uint32_t slot = frame % device().framesInFlight();
    gpu.update(slot, frame);
    device().submitNow([&](VkCommandBuffer commands) { gpu.recordSimulate(commands, slot); });
  }
  cpu.advance(66);
  const State mid = cpu.state();
  expectSameState(s, gpu.state(), mid);
  EXPECT_GT(crusted(mid), 0u);
  GpuSimulation resumed(device(), s);  // a resume from the CPU's state
  resumed.setState(mid);
  resumed.advance(60);
  cpu.advance(60);
  expectSameState(s, resumed.state(), cpu.state());
}

}  // namespace
}  // namespace lava
