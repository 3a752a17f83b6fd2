// The ring buffer (docs/model.md, "Emission"): exact counts for fractional rates, wrap-around that
// reuses the oldest slots, more than the capacity in one step.
#include <gtest/gtest.h>

#include <cmath>

#include "lava/simulation.h"
#include "sim/emission.h"

namespace lava {
namespace {

using detail::advanceClock;
using detail::Births;

// An emitter of `rate` per second into `capacity` slots.
Emitter emitter(double rate, uint32_t capacity) {
  Emitter e;
  e.rate = rate;
  e.particles = capacity;
  return e;
}

TEST(Emission, FractionalRateEmitsExactCounts) {
  EmitterClock clock;
  const float h = 0.001f;
  uint64_t total = 0;
  double owed = 0.0;
  for (int k = 0; k < 10000; ++k) {
    const Births e = advanceClock(clock, emitter(333.3, 5000), h, 0, uint64_t(k));
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
  EmitterClock clock;
  for (int k = 0; k < 4; ++k) advanceClock(clock, emitter(3000.0, 10), 0.001f, 0, k);  // 3 per step
  EXPECT_EQ(clock.head, 2u);
  EXPECT_EQ(clock.serial, 12u);
  const Births e = advanceClock(clock, emitter(3000.0, 10), 0.001f, 0, 4);
  EXPECT_EQ(e.head, 2u);
  EXPECT_EQ(e.count, 3u);
  EXPECT_EQ(e.firstSerial, 12u);
}

TEST(Emission, MoreThanCapacityInOneStepRebornsEverySlotOnce) {
  EmitterClock clock;
  const Births e = advanceClock(clock, emitter(20000.0, 8), 0.001f, 0, 0);  // 20 owed, 8 slots
  EXPECT_EQ(e.count, 8u);
  EXPECT_EQ(clock.head, 0u);
  EXPECT_EQ(clock.serial, 8u);
  EXPECT_LT(clock.accumulator, 1.0);
}

TEST(Emission, RingReusesTheOldestSlots) {
  Scene s;
  s.emitters[0].particles = 10;
  s.emitters[0].rate = 3000.0;  // 3 per step at h = 1 ms
  CpuSimulation sim(s);
  sim.advance(3);  // slots 0..8 born at steps 1, 2, 3
  std::vector<Particle> p = sim.state().particles;
  EXPECT_LT(p[9].age, 0.0f);  // never emitted
  EXPECT_FLOAT_EQ(p[0].age, 3 * s.h());
  EXPECT_FLOAT_EQ(p[8].age, 1 * s.h());
  sim.advance(1);  // step 4 fills 9, 0, 1: slot 9 is new, 0 and 1 (the oldest) are reborn
  p = sim.state().particles;
  EXPECT_FLOAT_EQ(p[9].age, s.h());
  EXPECT_FLOAT_EQ(p[0].age, s.h());
  EXPECT_FLOAT_EQ(p[1].age, s.h());
  EXPECT_FLOAT_EQ(p[2].age, 4 * s.h());  // survivor from step 1
  for (const Particle& q : p) EXPECT_GE(q.age, 0.0f);
}

TEST(Emission, ZeroRateLeavesEverySlotUnborn) {
  Scene s;
  s.emitters[0].rate = 0.0;
  CpuSimulation sim(s);
  sim.advance(100);
  for (const Particle& q : sim.state().particles) EXPECT_EQ(q.age, -1.0f);
}

TEST(Emission, RebornParticleGetsAFreshLaunch) {
  Scene s;
  s.emitters[0].particles = 4;
  s.emitters[0].rate = 4000.0;  // the whole ring every step
  CpuSimulation sim(s);
  sim.advance(1);
  const std::vector<Particle> first = sim.state().particles;
  sim.advance(1);
  const std::vector<Particle> second = sim.state().particles;
  for (int i = 0; i < 4; ++i) {
    EXPECT_FLOAT_EQ(second[i].age, s.h());
    EXPECT_NE(first[i].vx, second[i].vx);  // a new serial, new random draw
  }
}

}  // namespace
}  // namespace lava
