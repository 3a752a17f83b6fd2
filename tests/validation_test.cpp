// validateBackends on a backend that is wrong on purpose: the harness of `lava validate`
// must find the first divergent step and fail, or its "bit-exact" would mean nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "lava/validation.h"

namespace lava {
namespace {

// The CPU reference, with one velocity nudged by `ulps` after step `badStep`, every time
// that step is taken (so a replay meets it again).
class Nudged final : public Simulation {
 public:
  Nudged(const Scene& scene, uint64_t badStep, int ulps)
      : Simulation(scene), inner_(scene), badStep_(badStep), ulps_(ulps) {}
  void advance(uint64_t steps) override {
    for (uint64_t k = 0; k < steps; ++k) {
      inner_.advance(1);
      State s = inner_.state();
      if (s.step == badStep_) {
        float& v = s.particles[3].vy;
        for (int i = 0; i < ulps_; ++i) v = std::nextafter(v, 1e30f);
        inner_.setState(s);
      }
    }
  }
  State state() override { return inner_.state(); }
  void setState(const State& state) override { inner_.setState(state); }
  std::string name() const override { return "nudged"; }

 private:
  CpuSimulation inner_;
  uint64_t badStep_;
  int ulps_;
};

Scene smallScene() {
  Scene s;
  s.emitters[0].particles = 5000;
  s.emitters[0].rate =
      20000.0;  // 20 per step: slot 3 is born in step 1 and not reborn within 200 steps
  return s;
}

// validate() of the reference nudged by `ulps` after step `badStep` against the reference.
ValidationReport validateNudged(uint64_t badStep, int ulps, uint64_t steps, uint64_t every,
                                uint32_t toleranceUlp) {
  Nudged a(smallScene(), badStep, ulps);
  CpuSimulation b(smallScene());
  return validate(a, b, steps, every, toleranceUlp);
}

TEST(Validation, EqualBackendsPassWithNoDivergentStep) {
  CpuSimulation a(smallScene()), b(smallScene());
  const ValidationReport r = validate(a, b, 100, 10, 0);
  EXPECT_TRUE(r.pass);
  EXPECT_FALSE(r.firstDivergentStep);
  ASSERT_EQ(r.checkpoints.size(), 10u);
  EXPECT_EQ(r.checkpoints.back().step, 100u);
  for (const Checkpoint& c : r.checkpoints) EXPECT_EQ(c.comparison.equal, 5000u);
}

TEST(Validation, NamesTheFirstDivergentStepBetweenCheckpoints) {
  const ValidationReport r = validateNudged(37, 1, 100, 10, 0);
  EXPECT_FALSE(r.pass);
  ASSERT_TRUE(r.firstDivergentStep);
  EXPECT_EQ(*r.firstDivergentStep, 37u);
  ASSERT_TRUE(r.firstDifference);
  EXPECT_EQ(r.firstDifference->particle, 3u);
  EXPECT_EQ(r.firstDifference->field, 5u);  // vy
  EXPECT_EQ(r.firstDifference->subjectBits, r.firstDifference->referenceBits + 1);
  EXPECT_EQ(r.checkpoints[2].comparison.equal, 5000u);  // step 30: still equal
  EXPECT_EQ(r.checkpoints[3].comparison.equal, 4999u);  // step 40: slot 3 differs
  EXPECT_GE(r.checkpoints[3].comparison.maxUlp, 1u);
  // The divergence is carried on, not reset by the replay: later checkpoints still differ.
  EXPECT_LT(r.checkpoints.back().comparison.equal, 5000u);
}

TEST(Validation, ToleranceAcceptsSmallDifferencesButStillReportsThem) {
  const ValidationReport within = validateNudged(5, 1, 6, 6, 1000);
  EXPECT_TRUE(within.pass);
  ASSERT_TRUE(within.firstDivergentStep);
  EXPECT_EQ(*within.firstDivergentStep, 5u);
  EXPECT_FALSE(validateNudged(5, 1, 6, 6, 0).pass);
}

TEST(Validation, DivergenceAtTheVeryFirstStep) {
  const ValidationReport r = validateNudged(1, 4, 50, 25, 0);
  ASSERT_TRUE(r.firstDivergentStep);
  EXPECT_EQ(*r.firstDivergentStep, 1u);
}

}  // namespace
}  // namespace lava
