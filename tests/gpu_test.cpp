// The Vulkan backend against the CPU reference on lavapipe: bit-identical, deterministic,
// chunked past maxStorageBufferRange, validation-clean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "compare.h"
#include "cpu_simulator.h"
#include "gpu_simulator.h"
#include "state_io.h"
#include "vk_check.h"
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
  s.particles = 20000 + static_cast<uint32_t>(rng() % 5000);
  s.rate = uniform(1000.0f, 30000.0f);
  s.dt = uniform(0.0005f, 0.003f);
  s.gravity = uniform(1.0f, 20.0f);
  s.restitution = uniform(0.0f, 1.0f);
  s.friction = uniform(0.0f, 1.0f);
  s.emitter = {uniform(-2, 2), uniform(0, 3), uniform(-2, 2)};
  s.emitterRadius = uniform(0.0f, 1.0f);
  s.velocity = {uniform(-2, 2), uniform(2, 10), uniform(-2, 2)};
  s.spread = {uniform(0, 3), uniform(0, 3), uniform(0, 3)};
  s.mass = uniform(0.1f, 5.0f);
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
    GpuSimulator gpu(context(), s);
    CpuSimulator cpu(s, 0);
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
    s.particles = capacity;
    s.rate = rate;
    GpuSimulator gpu(context(), s);
    CpuSimulator cpu(s);
    for (uint64_t steps : {1u, 255u, 256u, 257u, 1000u}) {
      gpu.advance(steps);
      cpu.advance(steps);
      expectIdentical(gpu.state().particles, cpu.state().particles);
    }
  }
}

TEST_F(GpuTest, SeedSceneIsBitIdenticalAndPinned) {
  const Scene s;
  GpuSimulator gpu(context(), s);
  CpuSimulator cpu(s, 1);
  gpu.advance(5000);
  cpu.advance(5000);
  const std::vector<Particle> a = gpu.state().particles;
  expectIdentical(a, cpu.state().particles);
  // Pinned: a deliberate change to the physics or the random stream updates this value.
  EXPECT_EQ(stateHash(a), 0xfd75f27a9ab94144ull) << std::hex << "state hash 0x" << stateHash(a);
}

TEST_F(GpuTest, SameSeedSameBytesOtherSeedOtherBytes) {
  Scene s;
  s.particles = 4096;
  std::vector<Particle> runs[2];
  for (auto& run : runs) {
    GpuSimulator gpu(context(), s);
    gpu.advance(700);
    run = gpu.state().particles;
  }
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(Particle)));
  s.seed += 1;
  GpuSimulator other(context(), s);
  other.advance(700);
  EXPECT_NE(stateHash(other.state().particles), stateHash(runs[0]));
}

TEST_F(GpuTest, SerialCarryPast32BitsMatches) {
  Scene s;
  s.particles = 5000;
  s.rate = 50000.0;  // 50 per step: crosses 2^32 within the run
  SimState start = initialState(s);
  start.clock.serial = (uint64_t{1} << 32) - 1000;
  GpuSimulator gpu(context(), s);
  CpuSimulator cpu(s);
  gpu.load(start);
  cpu.load(start);
  gpu.advance(100);
  cpu.advance(100);
  EXPECT_GT(cpu.state().clock.serial, uint64_t{1} << 32);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, LoadAndStateRoundTrip) {
  Scene s;
  s.particles = 1000;
  CpuSimulator cpu(s);
  cpu.advance(1500);
  const SimState middle = cpu.state();
  GpuSimulator gpu(context(), s);
  gpu.load(middle);
  EXPECT_EQ(0, std::memcmp(gpu.state().particles.data(), middle.particles.data(),
                           middle.particles.size() * sizeof(Particle)));
  gpu.advance(500);
  cpu.advance(500);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, ManyChunksPastTheStorageBufferRange) {
  const uint32_t perChunk = particlesPerChunk(context());
  Scene s;
  s.particles = 16777216;
  s.rate = 2e10;  // capped at the capacity: the whole buffer is born in step 1
  s.dt = 0.001f;
  ASSERT_GT(uint64_t{s.particles} * sizeof(Particle), context().limits().maxStorageBufferRange);
  ASSERT_GT(s.particles, perChunk);
  GpuSimulator gpu(context(), s);
  // Each chunk is its own buffer and allocation, together covering every particle once.
  uint32_t next = 0;
  std::set<VkBuffer> buffers;
  for (const ParticleChunk& chunk : gpu.chunks()) {
    EXPECT_EQ(chunk.first, next);
    EXPECT_LE(chunk.count, perChunk);
    next += chunk.count;
    buffers.insert(chunk.buffer);
  }
  EXPECT_EQ(next, s.particles);
  EXPECT_EQ(buffers.size(), gpu.chunks().size());
  CpuSimulator cpu(s, 0);
  gpu.advance(3);
  cpu.advance(3);
  expectIdentical(gpu.state().particles, cpu.state().particles);
}

TEST_F(GpuTest, SoakOfAMillionStepsStaysBoundedAndBitIdentical) {
  const Scene s;  // the seed scene: 5000 slots, 1000/s, h = 1 ms
  GpuSimulator gpu(context(), s);
  CpuSimulator cpu(s, 0);
  gpu.advance(1000000);
  cpu.advance(1000000);
  const SimState state = gpu.state();
  EXPECT_EQ(state.clock.steps, 1000000u);
  EXPECT_GE(state.clock.serial, 999000u);
  const float oldest = float(s.particles) / float(s.rate) + 0.01f;  // ring lifetime (s)
  for (const Particle& p : state.particles) {
    ASSERT_GE(p.posAge.w, 0.0f) << "every slot is alive";
    ASSERT_LE(p.posAge.w, oldest);
    ASSERT_GE(p.posAge.y, 0.0f);
    for (int k = 0; k < 4; ++k) {
      ASSERT_TRUE(std::isfinite(p.posAge[k]));
      ASSERT_TRUE(std::isfinite(p.velMass[k]));
    }
  }
  expectIdentical(state.particles, cpu.state().particles);
}

TEST_F(GpuTest, TooManyParticlesIsAUsageError) {
  Scene s;
  s.particles = 0x80000000u;
  EXPECT_THROW(GpuSimulator(context(), s), UsageError);
}

}  // namespace
}  // namespace lava
