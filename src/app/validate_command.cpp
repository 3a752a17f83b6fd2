// `lava validate`: the same scene on the GPU and on the CPU reference, compared at
// checkpoints; on a difference, replays the last agreeing interval step by step to name
// the first divergent step.
#include <cstdio>
#include <optional>

#include "commands.h"
#include "compare.h"
#include "cpu_simulator.h"
#include "gpu_simulator.h"
#include "options.h"
#include "runtime.h"
#include "state_io.h"
#include "vk_check.h"

namespace lava::app {
namespace {

class ValidateCommand final : public Command {
 public:
  explicit ValidateCommand(CLI::App& app)
      : Command(app.add_subcommand("validate", "compare the GPU against the CPU reference")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "steps", Kind::Number, "steps to run, 1..1e9 (required)",
        [this](const std::string& src, const std::string& t) {
          steps_ = parseInteger(src, t, 1, 1000000000);
        },
        true);
    options_.add("every", Kind::Number, "compare every K steps, 1..1e9 [steps/10]",
                 [this](const std::string& src, const std::string& t) {
                   every_ = parseInteger(src, t, 1, 1000000000);
                 });
    options_.add("tolerance-ulp", Kind::Number, "largest accepted ULP distance, 0..2^31 [0]",
                 [this](const std::string& src, const std::string& t) {
                   tolerance_ = static_cast<uint32_t>(parseInteger(src, t, 0, 0x80000000u));
                 });
    options_.add("csv", Kind::Text, "also write the table to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   csv_ = t;
                 });
  }

  int run() override {
    options_.resolve();
    if (every_ == 0) every_ = std::max<uint64_t>(1, steps_ / 10);
    Context context(contextOptions(device_));
    GpuSimulator gpu(context, scene_);
    CpuSimulator cpu(scene_, 0);
    std::printf("validate: %u particles, %llu steps, gpu (%s) vs cpu reference, tolerance %u ULP\n",
                scene_.particles, static_cast<unsigned long long>(steps_),
                context.properties().deviceName, tolerance_);
    std::printf("%10s %21s %14s %14s %10s\n", "step", "equal particles", "max|dx| (m)",
                "max|dv| (m/s)", "max ULP");
    std::string table = "step,equal,particles,max_dx,max_dv,max_ulp\n";

    SimState agreed = cpu.state();  // the last checkpoint where both were bitwise equal
    std::optional<uint64_t> firstDivergent;
    bool pass = true;
    for (uint64_t step = 0; step < steps_;) {
      const uint64_t batch = std::min(every_, steps_ - step);
      gpu.advance(batch);
      cpu.advance(batch);
      step += batch;
      const SimState reference = cpu.state();
      const Comparison c = compare(gpu.state().particles, reference.particles);
      char row[160];
      std::snprintf(row, sizeof(row), "%10llu %10llu / %-8llu %14.6g %14.6g %10u\n",
                    static_cast<unsigned long long>(step), static_cast<unsigned long long>(c.equal),
                    static_cast<unsigned long long>(c.particles), c.maxDx, c.maxDv, c.maxUlp);
      std::fputs(row, stdout);
      std::snprintf(row, sizeof(row), "%llu,%llu,%llu,%.9g,%.9g,%u\n",
                    static_cast<unsigned long long>(step), static_cast<unsigned long long>(c.equal),
                    static_cast<unsigned long long>(c.particles), c.maxDx, c.maxDv, c.maxUlp);
      table += row;
      pass = pass && c.maxUlp <= tolerance_;
      if (c.equal == c.particles) {
        agreed = reference;
      } else if (!firstDivergent) {
        firstDivergent = findFirstDivergence(gpu, cpu, agreed, step);
        gpu.load(reference);  // both continue from the same state after the replay
        cpu.load(reference);
      }
    }
    if (!csv_.empty()) writeFileAtomically(csv_, table);
    if (firstDivergent)
      std::printf("first divergent step: %llu\n", static_cast<unsigned long long>(*firstDivergent));
    else
      std::printf("first divergent step: none (bit-exact over %llu steps)\n",
                  static_cast<unsigned long long>(steps_));
    std::printf("validate: %s\n", pass ? "PASS" : "FAIL");
    return finish(context, pass ? 0 : 1);
  }

 private:
  // Replays from `agreed` one step at a time until the backends differ (at most to `limit`).
  static uint64_t findFirstDivergence(Simulator& gpu, Simulator& cpu, const SimState& agreed,
                                      uint64_t limit) {
    gpu.load(agreed);
    cpu.load(agreed);
    for (uint64_t step = agreed.clock.steps + 1; step <= limit; ++step) {
      gpu.advance(1);
      cpu.advance(1);
      const Comparison c = compare(gpu.state().particles, cpu.state().particles);
      if (c.equal != c.particles) return step;
    }
    return limit;
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  uint64_t steps_ = 0;
  uint64_t every_ = 0;
  uint32_t tolerance_ = 0;
  std::string csv_;
};

}  // namespace

std::unique_ptr<Command> makeValidate(CLI::App& app) {
  return std::make_unique<ValidateCommand>(app);
}

}  // namespace lava::app
