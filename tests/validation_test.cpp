// validateBackends on a backend that is wrong on purpose: the harness of `lava validate`
// must find the first divergent step and fail, or its "bit-exact" would mean nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "cpu_simulator.h"
#include "validation.h"

namespace lava {
namespace {

// The CPU reference, with one velocity nudged by `ulps` after step `badStep`, every time
// that step is taken (so a replay meets it again).
class Nudged final : public Simulator {
 public:
  Nudged(const Scene& scene, uint64_t badStep, int ulps)
      : Simulator(scene), inner_(scene), badStep_(badStep), ulps_(ulps) {}
  void advance(uint64_t steps) override {
    for (uint64_t k = 0; k < steps; ++k) {
      inner_.advance(1);
      SimState s = inner_.state();
      if (s.clock.steps == badStep_) {
        float& v = s.particles[3].velMass.y;
        for (int i = 0; i < ulps_; ++i) v = std::nextafter(v, 1e30f);
        inner_.load(s);
      }
    }
  }
  SimState state() override { return inner_.state(); }
  void load(const SimState& state) override { inner_.load(state); }

 private:
  CpuSimulator inner_;
  uint64_t badStep_;
  int ulps_;
};

Scene smallScene() {
  Scene s;
  s.particles = 5000;
  s.rate = 20000.0;  // 20 per step: slot 3 is born in step 1 and not reborn within 200 steps
  return s;
}

TEST(Validation, EqualBackendsPassWithNoDivergentStep) {
  CpuSimulator a(smallScene()), b(smallScene());
  const ValidationReport r = validateBackends(a, b, 100, 10, 0);
  EXPECT_TRUE(r.pass);
  EXPECT_FALSE(r.firstDivergentStep);
  ASSERT_EQ(r.checkpoints.size(), 10u);
  EXPECT_EQ(r.checkpoints.back().step, 100u);
  for (const Checkpoint& c : r.checkpoints) EXPECT_EQ(c.comparison.equal, 5000u);
}

TEST(Validation, NamesTheFirstDivergentStepBetweenCheckpoints) {
  Nudged a(smallScene(), 37, 1);
  CpuSimulator b(smallScene());
  const ValidationReport r = validateBackends(a, b, 100, 10, 0);
  EXPECT_FALSE(r.pass);
  ASSERT_TRUE(r.firstDivergentStep);
  EXPECT_EQ(*r.firstDivergentStep, 37u);
  EXPECT_EQ(r.checkpoints[2].comparison.equal, 5000u);  // step 30: still equal
  EXPECT_EQ(r.checkpoints[3].comparison.equal, 4999u);  // step 40: slot 3 differs
  EXPECT_GE(r.checkpoints[3].comparison.maxUlp, 1u);
  // The divergence is carried on, not reset by the replay: later checkpoints still differ.
  EXPECT_LT(r.checkpoints.back().comparison.equal, 5000u);
}

TEST(Validation, ToleranceAcceptsSmallDifferencesButStillReportsThem) {
  Nudged a(smallScene(), 5, 1);
  CpuSimulator b(smallScene());
  const ValidationReport within = validateBackends(a, b, 6, 6, 1000);
  EXPECT_TRUE(within.pass);
  ASSERT_TRUE(within.firstDivergentStep);
  EXPECT_EQ(*within.firstDivergentStep, 5u);
  Nudged c(smallScene(), 5, 1);
  CpuSimulator d(smallScene());
  EXPECT_FALSE(validateBackends(c, d, 6, 6, 0).pass);
}

TEST(Validation, DivergenceAtTheVeryFirstStep) {
  Nudged a(smallScene(), 1, 4);
  CpuSimulator b(smallScene());
  const ValidationReport r = validateBackends(a, b, 50, 25, 0);
  ASSERT_TRUE(r.firstDivergentStep);
  EXPECT_EQ(*r.firstDivergentStep, 1u);
}

}  // namespace
}  // namespace lava
