// `lava validate`: the same scene on the GPU and on the CPU reference, compared at
// checkpoints (lava::validate) and printed as a table; or, with --suite, many cases with the
// reports CI tools read, against the CPU or against hashes recorded on another device.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <set>
#include <thread>

#include "commands.h"
#include "host/output.h"
#include "lava/checkpoint.h"
#include "lava/lava.h"
#include "lava/scene_keys.h"
#include "lava/validation.h"
#include "options.h"
#include "paths.h"
#include "resume.h"
#include "runtime.h"
#include "suite.h"

namespace lava::app {
namespace {

unsigned cores() {
  return std::max(1u, std::thread::hardware_concurrency());
}

class ValidateCommand final : public Command {
 public:
  explicit ValidateCommand(CLI::App& app)
      : Command(app, "validate", "compare the GPU against the CPU reference"), options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.addInteger("steps", "steps to run, 1..1e9 (required without --suite)", steps_, 1,
                        1000000000);
    options_.addInteger("every", "compare every K steps, 1..1e9 [steps/10]", every_, 1, 1000000000);
    options_.add("tolerance-ulp", "largest accepted ULP distance, 0..2^31 [0]",
                 [this](const std::string& src, const std::string& t) {
                   tolerance_ = static_cast<uint32_t>(parseInteger(src, t, 0, 0x80000000u));
                 });
    options_.add("reference",
                 "what computes the CPU side: cpu (the scalar reference) or cpu-simd (its SIMD "
                 "twin, the same bytes, faster for big scenes) [cpu]",
                 [this](const std::string& src, const std::string& t) {
                   if (t != "cpu" && t != "cpu-simd")
                     throw UsageError(src + ": expected cpu or cpu-simd, got '" + t + "'");
                   kernel_ = t == "cpu-simd" ? CpuKernel::Simd : CpuKernel::Reference;
                 });
    options_.add("csv", "also write the table to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   csv_ = t;
                 });
    options_.add("suite", "run a suite of cases: FILE.toml ([[case]] tables) or builtin",
                 [this](const std::string&, const std::string& t) { suite_ = t; });
    options_.add(
        "cases", "with --suite: run only these cases, NAME[,NAME...] in the suite's order",
        [this](const std::string& src, const std::string& t) { cases_ = splitCases(src, t); });
    options_.add("junit", "with --suite: write a JUnit XML report to FILE.xml",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".xml");
                   junit_ = t;
                 });
    options_.add("results", "with --suite: write case,status,... to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   results_ = t;
                 });
    options_.add("baseline", "with --suite: FILE of 'case,Fail' lines expected to fail",
                 [this](const std::string&, const std::string& t) { baseline_ = t; });
    options_.add("record", "with --suite: write each checkpoint's state hash to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   record_ = t;
                 });
    options_.add("against", "with --suite: compare the GPU to hashes --record wrote (no CPU)",
                 [this](const std::string&, const std::string& t) { against_ = t; });
    options_.add("resume",
                 "start both backends from the state a checkpoint FILE.npz holds, in its "
                 "scene (scene flags may change its parameters)",
                 [](const std::string&, const std::string&) {});  // read before resolve()
  }

  int run() override {
    resumed_ = readResume(options_, scene_);
    options_.resolve();
    if (resumed_) {
      checkResumedScene(scene_, resumed_->scene);
      if (!suite_.empty()) throw UsageError("--resume: not with --suite");
    }
    if (suite_.empty()) {
      for (const char* flag : {"cases", "junit", "results", "baseline", "record", "against"})
        if (options_.given(flag)) throw UsageError(std::string("--") + flag + ": needs --suite");
      if (steps_ == 0) throw UsageError("--steps is required: steps to run, 1..1e9");
      return single();
    }
    if (options_.given("steps") || options_.given("every") || options_.given("csv"))
      throw UsageError(std::string("--") +
                       (options_.given("steps")   ? "steps"
                        : options_.given("every") ? "every"
                                                  : "csv") +
                       ": the cases of a suite give their own (drop it with --suite)");
    return suite();
  }

 private:
  std::string referenceName() const {
    return kernel_ == CpuKernel::Simd ? "cpu-simd " + cpuSimdTarget() : "cpu reference";
  }

  void printDevice(const Device& device) const {
    std::printf("device: %s; %s\n", device.properties().deviceName, device.driver().c_str());
    std::printf("float controls: %s\n", device.floatControls().c_str());
    std::printf("optional paths: %s\n", device.optionalPaths().c_str());
  }

  int single() {
    if (every_ == 0) every_ = std::max<uint64_t>(1, steps_ / 10);
    Device device(deviceOptions(device_));
    GpuSimulation gpu(device, scene_);
    CpuSimulation cpu(scene_, cores(), kernel_);
    if (resumed_) {
      gpu.setState(resumed_->state);
      cpu.setState(resumed_->state);
    }
    std::printf("validate: %llu particles, %llu steps%s, %s vs %s, tolerance %u ULP\n",
                static_cast<unsigned long long>(scene_.particles()),
                static_cast<unsigned long long>(steps_),
                resumed_ ? (" from step " + std::to_string(resumed_->state.step) + " of " +
                            options_.text("resume"))
                               .c_str()
                         : "",
                gpu.name().c_str(), referenceName().c_str(), tolerance_);
    printDevice(device);
    std::printf("%10s %21s %10s %14s %14s %10s\n", "step", "bitwise-equal slots", "alive",
                "max|dx| (m)", "max|dv| (m/s)", "max ULP");
    std::string table = "step,equal,particles,alive,max_dx,max_dv,max_ulp\n";
    Progress progress("validate", steps_);
    const ValidationReport report =
        validate(gpu, cpu, steps_, every_, tolerance_, [&](const Checkpoint& point) {
          const Comparison& c = point.comparison;
          progress.clear();
          char row[160];
          std::snprintf(
              row, sizeof(row), "%10llu %10llu / %-8llu %10llu %14.6g %14.6g %10u\n",
              static_cast<unsigned long long>(point.step), static_cast<unsigned long long>(c.equal),
              static_cast<unsigned long long>(c.particles),
              static_cast<unsigned long long>(c.alive), double(c.maxDx), double(c.maxDv), c.maxUlp);
          std::fputs(row, stdout);
          std::snprintf(
              row, sizeof(row), "%llu,%llu,%llu,%llu,%.9g,%.9g,%u\n",
              static_cast<unsigned long long>(point.step), static_cast<unsigned long long>(c.equal),
              static_cast<unsigned long long>(c.particles),
              static_cast<unsigned long long>(c.alive), double(c.maxDx), double(c.maxDv), c.maxUlp);
          table += row;
          progress.update(point.step);
        });
    progress.clear();
    if (!csv_.empty()) host::writeFileAtomically(csv_, table);
    if (report.firstDivergentStep) {
      std::printf("first divergent step: %llu\n",
                  static_cast<unsigned long long>(*report.firstDivergentStep));
      if (report.firstDifference) {
        const Difference& d = *report.firstDifference;
        std::printf("first difference: particle %llu (emitter %u) %s: gpu 0x%08x, cpu 0x%08x\n",
                    static_cast<unsigned long long>(d.particle), d.emitter, fieldName(d.field),
                    d.subjectBits, d.referenceBits);
      }
    } else {
      std::printf("first divergent step: none (bit-exact over %llu steps)\n",
                  static_cast<unsigned long long>(steps_));
    }
    std::printf("validate: %s\n", report.pass ? "PASS" : "FAIL");
    return finish(device, report.pass ? 0 : 1);
  }

  // The case's scene with the scene flags given on the command line applied over it.
  Scene withFlags(Scene scene) const {
    for (const SceneKey& key : sceneKeys(KeyTable::Top))
      if (options_.given(key.name))
        setSceneKey(scene, KeyTable::Top, 0, key.name, options_.text(key.name));
    return scene;
  }

  CaseResult runCase(Device& device, const Case& c, const Recording* recording) const {
    CaseResult r;
    r.name = c.name;
    r.steps = c.steps;
    const Scene scene = withFlags(c.scene);
    const uint64_t every = c.every ? c.every : std::max<uint64_t>(1, c.steps / 10);
    const auto start = std::chrono::steady_clock::now();
    GpuSimulationOptions options;
    options.maxParticlesPerChunk = c.chunkParticles;
    GpuSimulation gpu(device, scene, options);
    State initial = initialState(scene);
    if (c.startSerial)
      for (EmitterClock& clock : initial.clocks) clock.serial = *c.startSerial;
    gpu.setState(initial);
    if (recording) {  // GPU against the hashes another run recorded
      const auto found = recording->find(c.name);
      bool pass = found != recording->end();
      if (!pass) r.message = "no hashes recorded for this case";
      for (uint64_t done = 0; pass && done < c.steps;) {
        const uint64_t batch = std::min(every, c.steps - done);
        gpu.advance(batch);
        done += batch;
        const uint64_t hash = stateHash(gpu.state());
        r.hashes.emplace_back(done, hash);
        const auto expected = found->second.find(done);
        if (expected == found->second.end()) {
          pass = false;
          r.message = "no hash recorded for step " + std::to_string(done);
        } else if (expected->second != hash) {
          pass = false;
          r.firstDivergentStep = done;
          char text[160];
          std::snprintf(
              text, sizeof(text), "state hash at step %llu is %016llx, the recording has %016llx",
              static_cast<unsigned long long>(done), static_cast<unsigned long long>(hash),
              static_cast<unsigned long long>(expected->second));
          r.message = text;
        }
      }
      r.status = pass ? Status::Pass : Status::Fail;
    } else {
      const std::unique_ptr<Simulation> cpu = referenceFor(scene, c.canary, cores(), kernel_);
      cpu->setState(initial);
      const ValidationReport report = validate(gpu, *cpu, c.steps, every, c.toleranceUlp);
      for (const Checkpoint& point : report.checkpoints) {
        r.hashes.emplace_back(point.step, point.subjectHash);
        r.maxUlp = std::max(r.maxUlp, point.comparison.maxUlp);
      }
      r.firstDivergentStep = report.firstDivergentStep;
      r.status = report.pass ? Status::Pass : Status::Fail;
      if (!report.pass) r.message = divergenceMessage(report, c.toleranceUlp);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  }

  // NAME[,NAME...]: each a name, none twice.
  static std::set<std::string> splitCases(const std::string& src, const std::string& text) {
    std::set<std::string> names;
    size_t start = 0;
    while (true) {
      const size_t comma = text.find(',', start);
      const std::string name = text.substr(start, comma - start);
      if (name.empty() || !names.insert(name).second)
        throw UsageError(src + ": expected case names, each once, separated by commas, got '" +
                         text + "'");
      if (comma == std::string::npos) return names;
      start = comma + 1;
    }
  }

  // The suite's cases that --cases names (all without it), in the suite's order.
  std::vector<Case> chosen(std::vector<Case> cases) const {
    if (cases_.empty()) return cases;
    for (const std::string& name : cases_)
      if (std::none_of(cases.begin(), cases.end(), [&](const Case& c) { return c.name == name; })) {
        std::string names;
        for (const Case& c : cases) names += (names.empty() ? "" : ", ") + c.name;
        throw UsageError("--cases: suite " + suite_ + " has no case '" + name + "' (it has " +
                         names + ")");
      }
    cases.erase(std::remove_if(cases.begin(), cases.end(),
                               [&](const Case& c) { return cases_.count(c.name) == 0; }),
                cases.end());
    return cases;
  }

  int suite() {
    Device device(deviceOptions(device_));
    const std::vector<Case> cases =
        chosen(suite_ == "builtin" ? builtinSuite(device) : loadSuite(suite_));
    const std::set<std::string> expectedFailures =
        baseline_.empty() ? std::set<std::string>{} : readBaseline(baseline_);
    std::optional<Recording> recording;
    if (!against_.empty()) recording = readRecording(against_);
    std::printf("validate: suite %s, %zu cases, %s vs %s\n", suite_.c_str(), cases.size(),
                device.properties().deviceName,
                recording ? ("hashes of " + against_).c_str() : referenceName().c_str());
    printDevice(device);
    std::vector<CaseResult> results;
    bool ok = true;
    Progress progress("validate", cases.size());
    for (const Case& c : cases) {
      CaseResult r = runCase(device, c, recording ? &*recording : nullptr);
      if (expectedFailures.count(c.name))
        r.status = r.status == Status::Fail ? Status::ExpectedFail : Status::UnexpectedPass;
      if (r.status == Status::UnexpectedPass)
        r.message = "passed, but the baseline expects it to fail";
      ok = ok && (r.status == Status::Pass || r.status == Status::ExpectedFail);
      std::printf("  %-32s %-14s %9llu steps %8u ULP %8.2f s%s%s\n", r.name.c_str(),
                  statusName(r.status), static_cast<unsigned long long>(r.steps), r.maxUlp,
                  r.seconds, r.message.empty() ? "" : "  ", r.message.c_str());
      std::fflush(stdout);
      results.push_back(std::move(r));
      progress.update(results.size());
    }
    for (const std::string& name : expectedFailures)
      if (std::none_of(cases.begin(), cases.end(), [&](const Case& c) { return c.name == name; }))
        std::printf("  (baseline lists '%s', which this suite does not have)\n", name.c_str());
    if (!results_.empty()) host::writeFileAtomically(results_, resultsCsv(results));
    if (!junit_.empty())
      host::writeFileAtomically(junit_, junitXml(results, device.properties().deviceName,
                                                 device.driver(), device.floatControls()));
    if (!record_.empty()) host::writeFileAtomically(record_, recordingText(results));
    std::printf("validate: %s\n", ok ? "PASS" : "FAIL");
    return finish(device, ok ? 0 : 1);
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  uint64_t steps_ = 0;
  uint64_t every_ = 0;
  uint32_t tolerance_ = 0;
  CpuKernel kernel_ = CpuKernel::Reference;
  std::string csv_, suite_, junit_, results_, baseline_, record_, against_;
  std::set<std::string> cases_;      // --cases
  std::optional<Snapshot> resumed_;  // --resume
};

}  // namespace

std::unique_ptr<Command> makeValidate(CLI::App& app) {
  return std::make_unique<ValidateCommand>(app);
}

}  // namespace lava::app
