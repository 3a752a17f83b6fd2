// The ring buffer of SPEC §2 step 1: exact counts for fractional rates, wrap-around that
// reuses the oldest slots, more than the capacity in one step.
#include <gtest/gtest.h>

#include <cmath>

#include "cpu_simulator.h"

namespace lava {
namespace {

TEST(Emission, FractionalRateEmitsExactCounts) {
  EmissionClock clock;
  const float h = 0.001f;
  uint64_t total = 0;
  double owed = 0.0;
  for (int k = 0; k < 10000; ++k) {
    const EmitStep e = clock.advance(333.3, h, 5000);
    owed += 333.3 * double(h);
    total += e.count;
    ASSERT_LE(e.count, 1u);
    ASSERT_NEAR(double(total), std::floor(owed), 1.0);
  }
  EXPECT_EQ(clock.serial, total);
  EXPECT_EQ(total, 3333u);
  EXPECT_NEAR(clock.accumulator, owed - 3333.0, 1e-9);
}

TEST(Emission, HeadWrapsAndSerialsCount) {
  EmissionClock clock;
  for (int k = 0; k < 4; ++k) clock.advance(3000.0, 0.001f, 10);  // 3 per step
  EXPECT_EQ(clock.head, 2u);
  EXPECT_EQ(clock.serial, 12u);
  const EmitStep e = clock.advance(3000.0, 0.001f, 10);
  EXPECT_EQ(e.head, 2u);
  EXPECT_EQ(e.count, 3u);
  EXPECT_EQ(e.firstSerial, 12u);
}

TEST(Emission, MoreThanCapacityInOneStepRebornsEverySlotOnce) {
  EmissionClock clock;
  const EmitStep e = clock.advance(20000.0, 0.001f, 8);  // 20 owed, 8 slots
  EXPECT_EQ(e.count, 8u);
  EXPECT_EQ(clock.head, 0u);
  EXPECT_EQ(clock.serial, 8u);
  EXPECT_LT(clock.accumulator, 1.0);
}

TEST(Emission, RingReusesTheOldestSlots) {
  Scene s;
  s.particles = 10;
  s.rate = 3000.0;  // 3 per step at h = 1 ms
  CpuSimulator sim(s);
  sim.advance(3);  // slots 0..8 born at steps 1, 2, 3
  std::vector<Particle> p = sim.state().particles;
  EXPECT_LT(p[9].posAge.w, 0.0f);  // never emitted
  EXPECT_FLOAT_EQ(p[0].posAge.w, 3 * s.dt);
  EXPECT_FLOAT_EQ(p[8].posAge.w, 1 * s.dt);
  sim.advance(1);  // step 4 fills 9, 0, 1: slot 9 is new, 0 and 1 (the oldest) are reborn
  p = sim.state().particles;
  EXPECT_FLOAT_EQ(p[9].posAge.w, s.dt);
  EXPECT_FLOAT_EQ(p[0].posAge.w, s.dt);
  EXPECT_FLOAT_EQ(p[1].posAge.w, s.dt);
  EXPECT_FLOAT_EQ(p[2].posAge.w, 4 * s.dt);  // survivor from step 1
  for (const Particle& q : p) EXPECT_GE(q.posAge.w, 0.0f);
}

TEST(Emission, ZeroRateLeavesEverySlotUnborn) {
  Scene s;
  s.rate = 0.0;
  CpuSimulator sim(s);
  sim.advance(100);
  for (const Particle& q : sim.state().particles) EXPECT_EQ(q.posAge.w, -1.0f);
}

TEST(Emission, RebornParticleGetsAFreshLaunch) {
  Scene s;
  s.particles = 4;
  s.rate = 4000.0;  // the whole ring every step
  CpuSimulator sim(s);
  sim.advance(1);
  const std::vector<Particle> first = sim.state().particles;
  sim.advance(1);
  const std::vector<Particle> second = sim.state().particles;
  for (int i = 0; i < 4; ++i) {
    EXPECT_FLOAT_EQ(second[i].posAge.w, s.dt);
    EXPECT_NE(first[i].velMass.x, second[i].velMass.x);  // a new serial, new random draw
  }
}

}  // namespace
}  // namespace lava
