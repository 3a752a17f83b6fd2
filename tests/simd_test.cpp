// cpu-simd: the SIMD kernel gives the reference's bytes, on every module and on
// random scenes drawing all of them, on 1 and 2 threads.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include <hwy/targets.h>

#include "lava/lava.h"
#include "lava/validation.h"
#include "sim/reference.h"
#include "sim/simd.h"
#include "test_scenes.h"

namespace lava {
namespace {

// Same bytes (not only equal floats: -0 and NaN payloads count), same clocks.
void expectSameBytes(const State& simd, const State& reference) {
  ASSERT_EQ(simd.particles.size(), reference.particles.size());
  size_t first = simd.particles.size();
  for (size_t i = 0; i < simd.particles.size() && first == simd.particles.size(); ++i)
    if (std::memcmp(&simd.particles[i], &reference.particles[i], sizeof(Particle)) != 0) first = i;
  EXPECT_EQ(first, simd.particles.size()) << "first differing slot " << first;
  ASSERT_EQ(simd.clocks.size(), reference.clocks.size());
  for (size_t k = 0; k < simd.clocks.size(); ++k) {
    EXPECT_EQ(simd.clocks[k].serial, reference.clocks[k].serial);
    EXPECT_EQ(simd.clocks[k].head, reference.clocks[k].head);
  }
  EXPECT_EQ(simd.step, reference.step);
}

size_t alive(const State& state) {
  size_t n = 0;
  for (const Particle& p : state.particles) n += p.age >= 0.0f;
  return n;
}

// The reference and the SIMD kernel on one and on two threads, stepped alike.
struct ReferenceAndSimd {
  ReferenceAndSimd(const Scene& s, unsigned referenceThreads)
      : reference(s, referenceThreads), one(s, 1, CpuKernel::Simd), two(s, 2, CpuKernel::Simd) {}
  // Steps all three `steps` further, the reference first.
  void advance(uint64_t steps) {
    reference.advance(steps);
    one.advance(steps);
    two.advance(steps);
  }
  // Expects both SIMD runs to hold the reference's bytes.
  void expectTheReferenceBytes() {
    expectSameBytes(one.state(), reference.state());
    expectSameBytes(two.state(), reference.state());
  }
  CpuSimulation reference, one, two;
};

class SimdModules : public ::testing::TestWithParam<const char*> {};

TEST_P(SimdModules, GiveTheReferenceBytesOnOneAndTwoThreads) {
  const Scene s = test::moduleScene(GetParam());
  ReferenceAndSimd runs(s, 2);
  for (int checkpoint = 0; checkpoint < 3; ++checkpoint) {
    runs.advance(1000);
    SCOPED_TRACE(std::string(GetParam()) + ", checkpoint " + std::to_string(checkpoint));
    runs.expectTheReferenceBytes();
    EXPECT_GT(alive(runs.reference.state()), 1000u);
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, SimdModules, ::testing::ValuesIn(test::moduleNames()),
                         test::moduleTestName);

TEST(Simd, RandomScenesOfEveryModuleGiveTheReferenceBytes) {
  std::mt19937 rng(15);
  for (int scene = 0; scene < 16; ++scene) {
    const Scene s = test::randomModuleScene(rng);
    ASSERT_NO_THROW(checkScene(s));
    SCOPED_TRACE("scene " + std::to_string(scene) + ": " + std::to_string(s.forces.size()) +
                 " forces, " + std::to_string(s.colliders.size()) + " colliders, " +
                 name(s.integrator));
    ReferenceAndSimd runs(s, 1);
    for (int checkpoint = 0; checkpoint < 2; ++checkpoint) {
      runs.advance(700);
      runs.expectTheReferenceBytes();
    }
  }
}

TEST(Simd, ResumesFromAReferenceStateAndBack) {
  const Scene s = test::moduleScene("all");
  CpuSimulation reference(s, 1), simd(s, 2, CpuKernel::Simd);
  reference.advance(500);
  simd.setState(reference.state());
  reference.advance(500);
  simd.advance(500);
  expectSameBytes(simd.state(), reference.state());
}

TEST(Simd, TheComputeCeilingKernelIsTheSameStep) {
  // The roofline microkernel steps a block in lanes: its bytes equal the scalar step's.
  const Scene s = test::moduleScene("emitter-disc");
  CpuSimulation fill(s, 1);
  fill.advance(3000);
  const State filled = fill.state();
  std::vector<Particle> lanes(filled.particles.begin(),
                              filled.particles.begin() + detail::kSimdBlock);
  std::vector<Particle> scalar = lanes;
  const detail::Reference reference(s);
  EXPECT_EQ(detail::stepKernelOnly(reference, lanes.data(), 400, false), 400 * detail::kSimdBlock);
  detail::stepKernelOnly(reference, scalar.data(), 400, true);
  EXPECT_EQ(std::memcmp(lanes.data(), scalar.data(), lanes.size() * sizeof(Particle)), 0);
}

TEST(Simd, EveryInstructionSetOfThisCpuGivesTheReferenceBytes) {
  // Highway compiled each target (SSSE3 ... AVX-512 here); the best runs by default, the
  // others are checked too, so a CPU without AVX-512 gets the same bytes.
  const std::vector<std::string> targets = cpuSimdTargets();
  ASSERT_FALSE(targets.empty());
  const Scene all = test::moduleScene("all");
  std::mt19937 rng(1515);
  const Scene random = test::randomModuleScene(rng);
  CpuSimulation a(all, 1), b(random, 1);
  a.advance(900);
  b.advance(900);
  for (const std::string& target : targets) {
    SCOPED_TRACE(target);
    CpuSimulation sa(all, 2, CpuKernel::Simd, target), sb(random, 1, CpuKernel::Simd, target);
    EXPECT_EQ(sa.simdTarget().rfind(target + " (", 0), 0u) << sa.simdTarget();
    sa.advance(900);
    sb.advance(900);
    expectSameBytes(sa.state(), a.state());
    expectSameBytes(sb.state(), b.state());
  }
  EXPECT_EQ(cpuSimdTarget().rfind(targets.front() + " (", 0), 0u) << cpuSimdTarget();
  EXPECT_EQ(CpuSimulation(all, 1, CpuKernel::Simd).simdTarget(), cpuSimdTarget());
  EXPECT_EQ(cpuSimdTarget(targets.back()),
            CpuSimulation(all, 1, CpuKernel::Simd, targets.back()).simdTarget());
  EXPECT_THROW(cpuSimdTarget("MMX"), InvalidArgument);
  try {
    CpuSimulation bad(all, 1, CpuKernel::Simd, "MMX");
    ADD_FAILURE() << "MMX accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "simd-target");
  }
}

// Two simulations on two instruction sets at once: the choice is each simulation's.
TEST(Simd, EachSimulationKeepsItsOwnTarget) {
  const std::vector<std::string> targets = cpuSimdTargets();
  const std::string last = targets.back();
  CpuSimulation best(test::moduleScene("all"), 1, CpuKernel::Simd);
  CpuSimulation other(test::moduleScene("all"), 1, CpuKernel::Simd, last);
  EXPECT_EQ(best.simdTarget(), cpuSimdTarget());
  EXPECT_EQ(other.simdTarget().rfind(last + " (", 0), 0u) << other.simdTarget();
  best.advance(300);
  other.advance(300);
  expectSameBytes(best.state(), other.state());
  EXPECT_EQ(best.simdTarget(), cpuSimdTarget()) << "the other simulation's choice leaked";
}

// Highway's target selection belongs to the process: a host that uses Highway itself must
// find it as it was, whatever target Lava runs.
TEST(Simd, ChoosingATargetLeavesHighwaysOwnSelectionAlone) {
  const int64_t supported = hwy::SupportedTargets();
  const bool initialized = hwy::GetChosenTarget().IsInitialized();
  const size_t index = hwy::GetChosenTarget().GetIndex();
  const std::vector<std::string> targets = cpuSimdTargets();
  for (const std::string& target : targets) {
    CpuSimulation simd(test::moduleScene("all"), 1, CpuKernel::Simd, target);
    simd.advance(10);
    EXPECT_EQ(simd.name().rfind("cpu-simd " + target + " (", 0), 0u) << simd.name();
    EXPECT_EQ(hwy::SupportedTargets(), supported) << target;
    EXPECT_EQ(hwy::GetChosenTarget().IsInitialized(), initialized) << target;
    EXPECT_EQ(hwy::GetChosenTarget().GetIndex(), index) << target;
  }
  EXPECT_EQ(cpuSimdTargets(), targets);
}

TEST(Simd, NamesItsInstructionSet) {
  const CpuSimulation simd(Scene{}, 2, CpuKernel::Simd);
  EXPECT_NE(simd.name().find("cpu-simd "), std::string::npos) << simd.name();
  EXPECT_NE(simd.name().find(" lanes), 2 threads"), std::string::npos) << simd.name();
  EXPECT_EQ(simd.kernel(), CpuKernel::Simd);
  EXPECT_EQ(CpuSimulation(Scene{}).name(), "cpu reference, 1 thread");
}

}  // namespace
}  // namespace lava
