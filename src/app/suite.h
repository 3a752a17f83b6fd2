// `lava validate --suite`: cases (a scene, a step count, a tolerance) run GPU against the CPU
// reference (or against recorded hashes), and the reports CI tools read: results CSV,
// JUnit XML, baselines of expected failures, per-checkpoint hashes (docs/cli.md, `lava validate`).
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lava/device.h"
#include "lava/scene.h"
#include "lava/simulation.h"
#include "lava/validation.h"

namespace lava::app {

struct Case {
  std::string name;
  Scene scene;
  uint64_t steps = 1000;
  uint64_t every = 0;  // 0: steps / 10
  uint32_t toleranceUlp = 0;
  std::optional<uint64_t> startSerial;  // every emitter's first serial (a serial near 2^32)
  uint32_t chunkParticles = 0;          // GpuSimulationOptions::maxParticlesPerChunk
  // A case that must fail: after this step the CPU reference's first alive particle has
  // its vy nudged by one ULP (a check that the reports and the CI around them notice).
  std::optional<uint64_t> canary;
};

// A suite file: [[case]] tables with name, steps, optional every, tolerance-ulp,
// start-serial and canary, and either scene = "file.toml" (relative to the suite) or scene keys
// inline (flat keys, [[case.emitter]], [[case.force]], [[case.collider]]). Throws UsageError naming
// the file, the case and the key.
std::vector<Case> loadSuite(const std::string& path);
// The same from the file's text; `path` names it, and its folder holds the scene files the
// cases name.
std::vector<Case> parseSuite(const std::string& text, const std::string& path);
// Lava's own suite for `device`: every shape, force, collider and integrator, bursts,
// lifetimes, fractional rates, a ring wrapping within one dispatch, more particles than one
// binding holds on the least device, a serial crossing 2^32, the denormal rule, all at once.
// The same scenes on every device, so that their hashes compare across devices.
std::vector<Case> builtinSuite(const Device& device);

enum class Status { Pass, Fail, ExpectedFail, UnexpectedPass };
const char* statusName(Status status);

// The CPU reference of `scene` (computed by `kernel`), nudged as `canary` says (or not at
// all; a canary always runs the scalar reference).
std::unique_ptr<Simulation> referenceFor(const Scene& scene, std::optional<uint64_t> canary,
                                         unsigned threads, CpuKernel kernel = CpuKernel::Reference);

struct CaseResult {
  std::string name;
  Status status = Status::Pass;
  uint64_t steps = 0;
  std::optional<uint64_t> firstDivergentStep;
  uint32_t maxUlp = 0;
  double seconds = 0.0;
  std::string message;                                // why it failed; empty when it passed
  std::vector<std::pair<uint64_t, uint64_t>> hashes;  // (step, state hash) per checkpoint
};

// Recorded hashes: case -> (step -> hash).
using Recording = std::map<std::string, std::map<uint64_t, uint64_t>>;
Recording readRecording(const std::string& path);
std::string recordingText(const std::vector<CaseResult>& results);

// Case names listed as `name,Fail` (comments with #, blank lines allowed).
std::set<std::string> readBaseline(const std::string& path);

std::string resultsCsv(const std::vector<CaseResult>& results);
std::string junitXml(const std::vector<CaseResult>& results, const std::string& device,
                     const std::string& driver, const std::string& floatControls);

// The message a failure carries: the first divergent step, the particle and its emitter,
// the field and both bit patterns.
std::string divergenceMessage(const ValidationReport& report, uint32_t toleranceUlp);

}  // namespace lava::app
