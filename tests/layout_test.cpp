// The GPU/CPU contract: struct layouts (also static_asserted in shared.h) and the random hash.
#include <gtest/gtest.h>

#include <cstddef>
#include <set>

#include "shared.h"

namespace lava::gpu {
namespace {

static_assert(offsetof(Particle, px) == 0 && offsetof(Particle, vx) == 16);
static_assert(offsetof(StepParams, material) == 64 && offsetof(StepParams, chunk) == 96);
static_assert(sizeof(StepParams) <= 128, "the minimum guaranteed push-constant size");

TEST(Layout, ParticleIsTwoVec4) {
  EXPECT_EQ(sizeof(Particle), 32u);
  EXPECT_EQ(alignof(Particle), alignof(float));
}

TEST(Random, HashIsPinned) {
  // Pinned (value computed independently in Python) so that a change to the hash, and so
  // to every emitted particle, is deliberate.
  EXPECT_EQ(hashMix(0u), 0u);
  EXPECT_EQ(hashMix(1u), 0x688990c0u) << std::hex << hashMix(1u);
  EXPECT_EQ(randomBits(7u, 1u, 0u, 2u), randomBits(7u, 1u, 0u, 2u));
  EXPECT_NE(randomBits(7u, 1u, 0u, 2u), randomBits(7u, 1u, 1u, 2u));  // high serial word counts
}

TEST(Random, SignedUnitCoversMinusOneToOneExactly) {
  EXPECT_EQ(signedUnit(0u), -1.0f);
  EXPECT_EQ(signedUnit(0xffffffffu), 1.0f - 1.0f / 8388608.0f);
  EXPECT_EQ(signedUnit(0x80000000u), 0.0f);
}

TEST(Random, StreamIsRoughlyUniformAndDistinct) {
  std::set<uint32_t> seen;
  double sum = 0.0;
  const int n = 100000;
  int buckets[10] = {};
  for (int i = 0; i < n; ++i) {
    const uint32_t bits = randomBits(20170101u, static_cast<uint32_t>(i), 0u, 0u);
    seen.insert(bits);
    const float u = signedUnit(bits);
    sum += u;
    buckets[static_cast<int>((u + 1.0f) * 5.0f)]++;
  }
  EXPECT_GT(seen.size(), static_cast<size_t>(n) - 5);  // few 32-bit collisions
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  for (int b : buckets) EXPECT_NEAR(b, n / 10, n / 100);
}

}  // namespace
}  // namespace lava::gpu
