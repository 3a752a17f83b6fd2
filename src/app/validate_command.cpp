// `lava validate`: the same scene on the GPU and on the CPU reference, compared at
// checkpoints (lava::validate), printed as a table.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <thread>

#include "commands.h"
#include "host/output.h"
#include "lava/lava.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

class ValidateCommand final : public Command {
 public:
  explicit ValidateCommand(CLI::App& app)
      : Command(app.add_subcommand("validate", "compare the GPU against the CPU reference")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "steps", "steps to run, 1..1e9 (required)",
        [this](const std::string& src, const std::string& t) {
          steps_ = parseInteger(src, t, 1, 1000000000);
        },
        true);
    options_.add("every", "compare every K steps, 1..1e9 [steps/10]",
                 [this](const std::string& src, const std::string& t) {
                   every_ = parseInteger(src, t, 1, 1000000000);
                 });
    options_.add("tolerance-ulp", "largest accepted ULP distance, 0..2^31 [0]",
                 [this](const std::string& src, const std::string& t) {
                   tolerance_ = static_cast<uint32_t>(parseInteger(src, t, 0, 0x80000000u));
                 });
    options_.add("csv", "also write the table to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   host::checkOutputPath(src, t, ".csv");
                   csv_ = t;
                 });
  }

  int run() override {
    options_.resolve();
    if (every_ == 0) every_ = std::max<uint64_t>(1, steps_ / 10);
    Device device(deviceOptions(device_));
    GpuSimulation gpu(device, scene_);
    CpuSimulation cpu(scene_, std::max(1u, std::thread::hardware_concurrency()));
    std::printf("validate: %llu particles, %llu steps, %s vs cpu reference, tolerance %u ULP\n",
                static_cast<unsigned long long>(scene_.particles()),
                static_cast<unsigned long long>(steps_), gpu.name().c_str(), tolerance_);
    std::printf("%10s %21s %14s %14s %10s\n", "step", "equal particles", "max|dx| (m)",
                "max|dv| (m/s)", "max ULP");
    std::string table = "step,equal,particles,max_dx,max_dv,max_ulp\n";

    const ValidationReport report =
        validate(gpu, cpu, steps_, every_, tolerance_, [&](const Checkpoint& point) {
          const Comparison& c = point.comparison;
          char row[160];
          std::snprintf(row, sizeof(row), "%10llu %10llu / %-8llu %14.6g %14.6g %10u\n",
                        static_cast<unsigned long long>(point.step),
                        static_cast<unsigned long long>(c.equal),
                        static_cast<unsigned long long>(c.particles), double(c.maxDx),
                        double(c.maxDv), c.maxUlp);
          std::fputs(row, stdout);
          std::snprintf(row, sizeof(row), "%llu,%llu,%llu,%.9g,%.9g,%u\n",
                        static_cast<unsigned long long>(point.step),
                        static_cast<unsigned long long>(c.equal),
                        static_cast<unsigned long long>(c.particles), double(c.maxDx),
                        double(c.maxDv), c.maxUlp);
          table += row;
        });
    if (!csv_.empty()) host::writeFileAtomically(csv_, table);
    if (report.firstDivergentStep)
      std::printf("first divergent step: %llu\n",
                  static_cast<unsigned long long>(*report.firstDivergentStep));
    else
      std::printf("first divergent step: none (bit-exact over %llu steps)\n",
                  static_cast<unsigned long long>(steps_));
    std::printf("validate: %s\n", report.pass ? "PASS" : "FAIL");
    return finish(device, report.pass ? 0 : 1);
  }

 private:
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
