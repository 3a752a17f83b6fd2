// `lava simulate`: runs a scene on the GPU or the CPU reference and writes the final state.
#include <chrono>
#include <cstdio>
#include <optional>

#include "commands.h"
#include "cpu_simulator.h"
#include "gpu_simulator.h"
#include "options.h"
#include "runtime.h"
#include "state_io.h"
#include "vk_check.h"

namespace lava::app {
namespace {

class SimulateCommand final : public Command {
 public:
  explicit SimulateCommand(CLI::App& app)
      : Command(app.add_subcommand("simulate", "run a scene headless and write its final state")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "steps", Kind::Number, "steps to run, 0..1e9 (required)",
        [this](const std::string& src, const std::string& t) {
          steps_ = parseInteger(src, t, 0, 1000000000);
        },
        true);
    options_.add("backend", Kind::Text, "gpu (the Vulkan device) or cpu (the reference) [gpu]",
                 [this](const std::string& src, const std::string& t) {
                   if (t != "gpu" && t != "cpu")
                     throw UsageError(src + ": expected gpu or cpu, got '" + t + "'");
                   gpu_ = t == "gpu";
                 });
    options_.add("threads", Kind::Number, "CPU backend threads, 0 = all cores, 0..1024 [0]",
                 [this](const std::string& src, const std::string& t) {
                   threads_ = static_cast<unsigned>(parseInteger(src, t, 0, 1024));
                 });
    options_.add("out", Kind::Text, "write the final state to FILE.npy or FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkStatePath(src, t);
                   out_ = t;
                 });
  }

  int run() override {
    options_.resolve();
    std::optional<Context> context;
    std::unique_ptr<Simulator> simulator;
    std::string where = "cpu reference";
    if (gpu_) {
      context.emplace(contextOptions(device_));
      simulator = std::make_unique<GpuSimulator>(*context, scene_);
      where = std::string("gpu (") + context->properties().deviceName + ")";
    } else {
      auto cpu = std::make_unique<CpuSimulator>(scene_, threads_);
      where = "cpu reference, " + std::to_string(cpu->threads()) + " thread(s)";
      simulator = std::move(cpu);
    }

    const auto start = std::chrono::steady_clock::now();
    {
      Progress progress("simulate", steps_);
      for (uint64_t done = 0; done < steps_;) {
        const uint64_t batch = std::min<uint64_t>(steps_ - done, 4096);
        simulator->advance(batch);
        done += batch;
        progress.update(done);
      }
    }
    const SimState state = simulator->state();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    uint64_t alive = 0, below = 0;
    for (const Particle& p : state.particles) {
      alive += p.posAge.w >= 0.0f;
      below += p.posAge.w >= 0.0f && p.posAge.y < 0.0f;
    }
    if (!out_.empty()) writeState(out_, state.particles);
    std::printf(
        "simulate: %u particles x %llu steps on %s in %s: %llu alive, %llu below ground, "
        "state hash %016llx%s%s\n",
        scene_.particles, static_cast<unsigned long long>(steps_), where.c_str(),
        formatSeconds(seconds).c_str(), static_cast<unsigned long long>(alive),
        static_cast<unsigned long long>(below),
        static_cast<unsigned long long>(stateHash(state.particles)), out_.empty() ? "" : ", wrote ",
        out_.c_str());
    return context ? finish(*context, 0) : 0;
  }

 private:
  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  uint64_t steps_ = 0;
  bool gpu_ = true;
  unsigned threads_ = 0;
  std::string out_;
};

}  // namespace

std::unique_ptr<Command> makeSimulate(CLI::App& app) {
  return std::make_unique<SimulateCommand>(app);
}

}  // namespace lava::app
