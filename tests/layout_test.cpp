// The GPU/CPU contract: the random hash pinned to values computed apart (in Python), its
// float conversion, and its spread. (Struct layouts are static_asserted in shared.h and
// checked against the compiled SPIR-V in spirv_test.cpp.)
#include <gtest/gtest.h>

#include <cstddef>
#include <set>

#include "shared.h"

namespace lava::gpu {
namespace {

static_assert(offsetof(Particle, px) == 0 && offsetof(Particle, vx) == 16);
static_assert(sizeof(StepParams) <= 128, "the minimum guaranteed push-constant size");

TEST(Random, HashIsPinned) {
  // Pinned to values computed independently in Python, so that a change to the hash, and
  // so to every emitted particle, is deliberate.
  EXPECT_EQ(hashMix(1u), 0x688990c0u) << std::hex << hashMix(1u);
  EXPECT_EQ(hashMix(0x12345678u), 0xf5e71c96u) << std::hex << hashMix(0x12345678u);
  EXPECT_EQ(randomBits(7u, 1u, 0u, 2u), 0xe2e872e3u);
  EXPECT_EQ(randomBits(7u, 1u, 1u, 2u), 0xb3d6f575u);  // the serial's high word counts
  EXPECT_EQ(randomBits(20170101u, 0u, 0u, 0u), 0x6d0f5089u);
  EXPECT_EQ(randomBits(20170101u, 12345u, 0u, 3u), 0xf66e00b6u);
  EXPECT_EQ(randomBits(0xffffffffu, 0xffffffffu, 0xffffffffu, 31u), 0xb0d7ce99u);
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

// The splat's sums in 2 x 8 blocks: every pixel of a target its own index, within the
// target rounded up to whole blocks, a block's 16 pixels in one 64-byte line, and two
// pixels one above the other (the upper on an even row) in one 8-byte word.
static_assert(kSplatBlockWidth * kSplatBlockHeight * sizeof(uint) == 64, "a block is a cache line");
static_assert(kSplatBlockHeight % 2u == 0u, "a pair of rows never straddles two blocks");
TEST(SplatLayout, EveryPixelHasItsOwnIndexWithinWholeBlocks) {
  for (const auto& [width, height] : {std::pair{1u, 1u}, {5u, 3u}, {8u, 8u}, {1281u, 17u}}) {
    const uint blocks = ((width + 1u) / 2u) * ((height + 7u) / 8u);
    std::set<uint> seen;
    for (uint y = 0; y < height; ++y)
      for (uint x = 0; x < width; ++x) {
        const uint at = splatIndex(x, y, width);
        EXPECT_LT(at, blocks * 16u) << x << ", " << y << " of " << width << "x" << height;
        seen.insert(at);
        EXPECT_EQ(at / 16u, splatIndex(x & ~1u, y & ~7u, width) / 16u);
        // A pixel on an even row and the one below it: one 8-byte word, the upper low.
        if (y % 2u == 0u) {
          EXPECT_EQ(at % 2u, 0u);
          EXPECT_EQ(splatIndex(x, y + 1u, width), at + 1u);
        }
      }
    EXPECT_EQ(seen.size(), size_t{width} * height);
  }
}

}  // namespace
}  // namespace lava::gpu
