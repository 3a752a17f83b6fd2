// The Vulkan backend against the CPU reference on lavapipe: bit-identical, deterministic,
// chunked past maxStorageBufferRange, validation-clean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "lava/lava.h"
#include "lava/validation.h"
#include "lava/checkpoint.h"
#include "test_scenes.h"
#include "vulkan_test.h"

namespace lava {
namespace {

using GpuTest = test::VulkanTest;

void expectIdentical(const std::vector<Particle>& gpu, const std::vector<Particle>& cpu) {
  const Comparison c = compare(gpu, cpu);
  EXPECT_EQ(c.equal, c.particles) << "max ULP " << c.maxUlp << ", max |dx| " << c.maxDx
                                  << ", max |dv| " << c.maxDv;
}

Scene randomScene(std::mt19937& rng) {
  auto uniform = [&](float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(rng);
  };
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = 20000 + static_cast<uint32_t>(rng() % 5000);
  e.rate = uniform(1000.0f, 30000.0f);
  s.dt = uniform(0.0005f, 0.003f);
  s.gravity = uniform(1.0f, 20.0f);
  s.restitution = uniform(0.0f, 1.0f);
  s.friction = uniform(0.0f, 1.0f);
  e.position = {uniform(-2, 2), uniform(0, 3), uniform(-2, 2)};
  e.radius = uniform(0.0f, 1.0f);
  e.velocity = {uniform(-2, 2), uniform(2, 10), uniform(-2, 2)};
  e.spread = {uniform(0, 3), uniform(0, 3), uniform(0, 3)};
  e.mass = uniform(0.1f, 5.0f);
  s.wind = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
  s.drag = uniform(0.0f, 0.5f);
  s.seed = static_cast<uint32_t>(rng());
  return s;
}

TEST_F(GpuTest, RandomScenesAreBitIdenticalToTheCpuReference) {
  std::mt19937 rng(1234);
  for (int scene = 0; scene < 4; ++scene) {
    const Scene s = randomScene(rng);
    SCOPED_TRACE("scene " + std::to_string(scene) + ", seed " + std::to_string(s.seed));
    GpuSimulation gpu(device(), s);
    CpuSimulation cpu(s, 2);
    for (int checkpoint = 0; checkpoint < 3; ++checkpoint) {
      gpu.advance(1000);
      cpu.advance(1000);
      expectIdentical(gpu.state().particles, cpu.state().particles);
    }
  }
}

TEST_F(GpuTest, RingWrapsManyTimesWithinOneDispatch) {
  // step.comp finds each slot's last birth in a dispatch arithmetically; these scenes wrap
  // the ring several times per dispatch, fill it whole every step, or barely emit.
  const std::pair<uint32_t, double> cases[] = {{7, 3000.0},   {64, 64000.0}, {100, 1e9},
                                               {5000, 333.3}, {1, 500.0},    {4099, 123456.7}};
  for (const auto& [capacity, rate] : cases) {
    SCOPED_TRACE("capacity " + std::to_string(capacity) + ", rate " + std::to_string(rate));
    Scene s;
    s.emitters[0].particles = capacity;
    s.emitters[0].rate = rate;
    GpuSimulation gpu(device(), s);
    CpuSimulation cpu(s);
    for (uint64_t steps : {1u, 255u, 256u, 257u, 1000u}) {
      gpu.advance(steps);
      cpu.advance(steps);
      expectIdentical(gpu.state().particles, cpu.state().particles);
    }
  }
}

TEST_F(GpuTest, BirthsOfManyEmittersLandWhereTheFullStepRuns) {
  // Only the workgroups a dispatch's births land on run step.comp's birth search; the rest
  // (where at least 32 workgroups in a row have none) run it without. Rings large enough for
  // that: births that wrap their ring within a dispatch (1 emitter), that wrap the
  // invocations' four strides (2), that fill a ring several times (3), and emitters spread
  // over more ranges than a dispatch splits into (12: the whole chunk runs the full step).
  struct Case {
    size_t emitters;
    uint32_t particles, more;  // emitter k has particles + k * more
    double rate;               // births per second of the last emitter
    uint64_t last;             // steps of the last advance
  };
  for (const Case& c : {Case{1, 50000, 0, 2.5e4, 2000}, Case{2, 40000, 97, 2e5, 300},
                        Case{3, 30011, 97, 3e6, 300}, Case{12, 8000, 2003, 900.0, 300}}) {
    SCOPED_TRACE(std::to_string(c.emitters) + " emitters of " + std::to_string(c.particles) +
                 ", rate " + std::to_string(c.rate));
    Scene s;
    const Emitter first = s.emitters[0];
    s.emitters.assign(c.emitters, first);
    for (size_t k = 0; k < c.emitters; ++k) {
      s.emitters[k].particles = c.particles + c.more * uint32_t(k);
      s.emitters[k].rate = c.rate * double(k + 1) / double(c.emitters);
      s.emitters[k].velocity.x = 0.25f * float(k);
    }
    GpuSimulation gpu(device(), s);
    CpuSimulation cpu(s);
    for (uint64_t steps : {uint64_t{1}, uint64_t{40}, uint64_t{256}, c.last}) {
      gpu.advance(steps);
      cpu.advance(steps);
      expectIdentical(gpu.state().particles, cpu.state().particles);
    }
  }
}

TEST_F(GpuTest, SeedSceneIsBitIdenticalAndPinned) {
  const Scene s;
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 1);
  gpu.advance(5000);
  cpu.advance(5000);
  const std::vector<Particle> a = gpu.state().particles;
  expectIdentical(a, cpu.state().particles);
  // Pinned: a deliberate change to the physics or the random stream updates this value.
  EXPECT_EQ(stateHash(a), 0xfd75f27a9ab94144ull) << std::hex << "state hash 0x" << stateHash(a);
}

TEST_F(GpuTest, SameSeedSameBytesOtherSeedOtherBytes) {
  Scene s;
  s.emitters[0].particles = 4096;
  std::vector<Particle> runs[2];
  for (auto& run : runs) {
    GpuSimulation gpu(device(), s);
    gpu.advance(700);
    run = gpu.state().particles;
  }
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(Particle)));
  s.seed += 1;
  GpuSimulation other(device(), s);
  other.advance(700);
  EXPECT_NE(stateHash(other.state().particles), stateHash(runs[0]));
}

TEST_F(GpuTest, SerialCarryPast32BitsMatches) {
  Scene s;
  s.emitters[0].particles = 5000;
  s.emitters[0].rate = 50000.0;  // 50 per step: crosses 2^32 within the run
  State start = initialState(s);
  start.clocks[0].serial = (uint64_t{1} << 32) - 1000;
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s);
  gpu.setState(start);
  cpu.setState(start);
  gpu.advance(100);
  cpu.advance(100);
  EXPECT_GT(cpu.state().clocks[0].serial, uint64_t{1} << 32);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, LoadAndStateRoundTrip) {
  Scene s;
  s.emitters[0].particles = 1000;
  CpuSimulation cpu(s);
  cpu.advance(1500);
  const State middle = cpu.state();
  GpuSimulation gpu(device(), s);
  gpu.setState(middle);
  EXPECT_EQ(0, std::memcmp(gpu.state().particles.data(), middle.particles.data(),
                           middle.particles.size() * sizeof(Particle)));
  gpu.advance(500);
  cpu.advance(500);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, ManyChunksPastTheStorageBufferRange) {
  const uint32_t perChunk = device().particlesPerChunk();
  Scene s;
  s.emitters[0].particles = 16777216;
  s.emitters[0].burst = 16777216;  // the whole buffer is born in step 1
  // Past the storage range on lavapipe (128 MiB); past the texel views elsewhere.
  ASSERT_GT(s.particles(), perChunk);
  GpuSimulation gpu(device(), s);
  // Each chunk is its own buffer and allocation, together covering every particle once.
  uint64_t next = 0;
  std::set<VkBuffer> buffers;
  for (const ParticleChunk& chunk : gpu.chunks()) {
    EXPECT_EQ(chunk.first, next);
    EXPECT_LE(chunk.count, perChunk);
    next += chunk.count;
    buffers.insert(chunk.buffer);
  }
  EXPECT_EQ(next, s.particles());
  EXPECT_EQ(buffers.size(), gpu.chunks().size());
  CpuSimulation cpu(s, 2);
  gpu.advance(3);
  cpu.advance(3);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, SoakOfAMillionStepsStaysBoundedAndBitIdentical) {
  const Scene s;  // the default scene (the lab handout's): 5000 slots, 1000/s, h = 1 ms
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2, CpuKernel::Simd);  // the reference's bytes (Simd.*), in less time
  gpu.advance(1000000);
  cpu.advance(1000000);
  const State state = gpu.state();
  EXPECT_EQ(state.step, 1000000u);
  EXPECT_GE(state.clocks[0].serial, 999000u);
  const float oldest = float(s.particles()) / float(s.emitters[0].rate) + 0.01f;  // ring lifetime
  for (const Particle& p : state.particles) {
    ASSERT_GE(p.age, 0.0f) << "every slot is alive";
    ASSERT_LE(p.age, oldest);
    ASSERT_GE(p.py, 0.0f);
    for (float f : {p.px, p.py, p.pz, p.age, p.vx, p.vy, p.vz, p.mass})
      ASSERT_TRUE(std::isfinite(f));
  }
  expectIdentical(state.particles, cpu.state().particles);
}

TEST_F(GpuTest, TooManyParticlesIsAnInvalidArgument) {
  // One more than this device holds (not a fixed count that a large GPU would allocate).
  Scene s;
  s.emitters[0].particles = static_cast<uint32_t>(device().maxParticles() + 1);
  try {
    GpuSimulation gpu(device(), s);
    ADD_FAILURE() << "no error for " << s.particles() << " particles";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "particles") << e.what();
  }
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {
using test::moduleScene;

class Modules : public test::VulkanTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(Modules, AreBitIdenticalToTheCpuReference) {
  const Scene s = moduleScene(GetParam());
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  for (int checkpoint = 0; checkpoint < 3; ++checkpoint) {
    gpu.advance(1000);
    cpu.advance(1000);
    const Comparison c = compare(s, gpu.state(), cpu.state());  // a flow's heat too
    ASSERT_EQ(c.equal, c.particles)
        << GetParam() << ": first difference at slot " << (c.first ? c.first->particle : 0)
        << " (" << (c.first ? fieldName(c.first->field) : "") << "), max ULP " << c.maxUlp;
    EXPECT_GT(c.alive, 1000u);
  }
}

// Checkpoints: N steps straight, or N/2, a checkpoint (through its bytes, as a
// file holds them), then N/2 more: the same bytes, on each backend and crossed over.
TEST_P(Modules, ResumeFromACheckpointBitForBit) {
  const Scene s = moduleScene(GetParam());
  CpuSimulation straight(s, 2);
  straight.advance(1200);
  const State expected = straight.state();
  for (int first = 0; first < 2; ++first)
    for (int second = 0; second < 2; ++second) {
      SCOPED_TRACE(std::string(first ? "gpu" : "cpu") + " then " + (second ? "gpu" : "cpu"));
      std::unique_ptr<Simulation> a, b;
      if (first)
        a = std::make_unique<GpuSimulation>(device(), s);
      else
        a = std::make_unique<CpuSimulation>(s, 1);
      a->advance(600);
      const Snapshot saved = parseCheckpoint(checkpointBytes(s, a->state()), "test");
      EXPECT_EQ(saved.state.step, 600u);
      if (second)
        b = std::make_unique<GpuSimulation>(device(), saved.scene);
      else
        b = std::make_unique<CpuSimulation>(saved.scene, 2);
      b->setState(saved.state);
      b->advance(600);
      const State got = b->state();
      ASSERT_EQ(got.particles.size(), expected.particles.size());
      EXPECT_EQ(std::memcmp(got.particles.data(), expected.particles.data(),
                            got.particles.size() * sizeof(Particle)),
                0);
      ASSERT_EQ(got.temperature.size(), expected.temperature.size());  // a flow's heat
      if (!got.temperature.empty()) {  // (memcmp must not be given a null pointer)
        EXPECT_EQ(std::memcmp(got.temperature.data(), expected.temperature.data(),
                              got.temperature.size() * sizeof(float)),
                  0);
      }
      EXPECT_EQ(got.crust, expected.crust);
      EXPECT_EQ(got.step, expected.step);
      for (size_t k = 0; k < got.clocks.size(); ++k) {
        EXPECT_EQ(got.clocks[k].serial, expected.clocks[k].serial);
        EXPECT_EQ(got.clocks[k].head, expected.clocks[k].head);
        EXPECT_EQ(got.clocks[k].accumulator, expected.clocks[k].accumulator);
      }
    }
}

// Behaviour the panel and embedders rely on.
TEST_F(GpuTest, SceneChangesMidRunStayBitIdenticalToTheCpu) {
  // The panel's live edits: parameters change between steps (rate, gravity, wind, drag, the
  // ground, an emitter's velocity and a collider's place), on both backends alike.
  Scene s = moduleScene("all");
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2);
  for (int change = 0; change < 3; ++change) {
    gpu.advance(400);
    cpu.advance(400);
    s.gravity = 9.81f + float(change);
    s.wind = {0.3f * float(change), 0.0f, -0.2f};
    s.drag = 0.05f * float(change + 1);
    s.restitution = 0.3f + 0.1f * float(change);
    s.emitters[0].rate = 2000.0 + 500.0 * change;
    s.emitters[0].velocity.y = 5.0f + float(change);
    if (!s.colliders.empty()) s.colliders[0].position.x = 0.1f * float(change);
    gpu.setScene(s);
    cpu.setScene(s);
  }
  gpu.advance(400);
  cpu.advance(400);
  const Comparison c = compare(s, gpu.state().particles, cpu.state().particles);
  EXPECT_EQ(c.equal, c.particles) << "max ULP " << c.maxUlp;
  // A restart (the panel's "restart with this scene"): a fresh simulation of the edited
  // scene, both backends.
  GpuSimulation again(device(), s);
  CpuSimulation againCpu(s, 1);
  again.advance(500);
  againCpu.advance(500);
  EXPECT_EQ(stateHash(again.state().particles), stateHash(againCpu.state().particles));
}

TEST_F(GpuTest, ADispatchOfMoreThan2To31BirthsIsSplit) {
  // 2^23 slots all reborn every step (births are capped at the capacity): 256 steps fused
  // would hold 2^31 births of one emitter, past the shader's 32-bit sums, so the plan
  // splits the dispatch. The result must not notice.
  Scene s;
  s.dt = 0.01;
  s.emitters[0].particles = 1u << 23;
  s.emitters[0].rate = 1e9;
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 2, CpuKernel::Simd);  // the reference's bytes (Simd.*), in less time
  gpu.advance(256);
  cpu.advance(256);
  const State g = gpu.state(), c = cpu.state();
  EXPECT_EQ(stateHash(g.particles), stateHash(c.particles));
  EXPECT_EQ(g.clocks[0].serial, uint64_t{256} << 23);
  EXPECT_EQ(c.clocks[0].serial, uint64_t{256} << 23);
}

TEST_F(GpuTest, CpuThreadCountsOneToEightGiveTheSameBytes) {
  const Scene s = moduleScene("all");
  CpuSimulation one(s, 1);
  one.advance(700);
  const uint64_t expected = stateHash(one.state().particles);
  for (unsigned threads = 2; threads <= 8; ++threads) {
    CpuSimulation many(s, threads);
    many.advance(700);
    EXPECT_EQ(stateHash(many.state().particles), expected) << threads << " threads";
  }
}

TEST_F(GpuTest, AStateOfTheWrongSizeIsRefusedByBothBackends) {
  const Scene s = moduleScene("emitter-disc");
  State wrong = initialState(s);
  wrong.particles.pop_back();
  GpuSimulation gpu(device(), s);
  CpuSimulation cpu(s, 1);
  EXPECT_THROW(gpu.setState(wrong), InvalidArgument);
  EXPECT_THROW(cpu.setState(wrong), InvalidArgument);
  wrong = initialState(s);
  wrong.clocks.push_back({});
  EXPECT_THROW(gpu.setState(wrong), InvalidArgument);
  wrong = initialState(s);
  wrong.clocks[0].head = s.emitters[0].particles;
  EXPECT_THROW(gpu.setState(wrong), InvalidArgument);
  EXPECT_THROW(cpu.setState(wrong), InvalidArgument);
}

INSTANTIATE_TEST_SUITE_P(Effects, Modules, ::testing::ValuesIn(test::moduleNames()),
                         test::moduleTestName);

}  // namespace
}  // namespace lava
