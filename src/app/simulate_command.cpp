// `lava simulate`: runs a scene on the GPU or the CPU reference and writes the final state.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include "commands.h"
#include "host/output.h"
#include "lava/lava.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

class SimulateCommand final : public Command {
 public:
  explicit SimulateCommand(CLI::App& app)
      : Command(app.add_subcommand("simulate", "run a scene headless and write its final state")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "steps", "steps to run, 0..1e9 (required)",
        [this](const std::string& src, const std::string& t) {
          steps_ = parseInteger(src, t, 0, 1000000000);
        },
        true);
    options_.add("backend", "gpu (the Vulkan device) or cpu (the reference) [gpu]",
                 [this](const std::string& src, const std::string& t) {
                   if (t != "gpu" && t != "cpu")
                     throw host::UsageError(src + ": expected gpu or cpu, got '" + t + "'");
                   gpu_ = t == "gpu";
                 });
    options_.add("threads", "CPU backend threads, 0 = all cores, 0..1024 [0]",
                 [this](const std::string& src, const std::string& t) {
                   threads_ = static_cast<unsigned>(parseInteger(src, t, 0, 1024));
                 });
    options_.add("out", "write the final state to FILE.npy or FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   host::checkStatePath(src, t);
                   out_ = t;
                 });
  }

  int run() override {
    options_.resolve();
    std::unique_ptr<Device> device;
    std::unique_ptr<Simulation> simulation;
    if (gpu_) {
      device = std::make_unique<Device>(deviceOptions(device_));
      simulation = std::make_unique<GpuSimulation>(*device, scene_);
    } else {
      const unsigned threads =
          threads_ ? threads_ : std::max(1u, std::thread::hardware_concurrency());
      simulation = std::make_unique<CpuSimulation>(scene_, threads);
    }

    const auto start = std::chrono::steady_clock::now();
    {
      Progress progress("simulate", steps_);
      for (uint64_t done = 0; done < steps_;) {
        const uint64_t batch = std::min<uint64_t>(steps_ - done, 4096);
        simulation->advance(batch);
        done += batch;
        progress.update(done);
      }
    }
    const State state = simulation->state();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    uint64_t alive = 0, below = 0;
    for (const Particle& p : state.particles) {
      alive += p.age >= 0.0f;
      below += p.age >= 0.0f && p.py < 0.0f;
    }
    if (!out_.empty()) host::writeState(out_, state.particles);
    std::printf(
        "simulate: %llu particles x %llu steps on %s in %s: %llu alive, %llu below ground, "
        "state hash %016llx%s%s\n",
        static_cast<unsigned long long>(scene_.particles()),
        static_cast<unsigned long long>(steps_), simulation->name().c_str(),
        formatSeconds(seconds).c_str(), static_cast<unsigned long long>(alive),
        static_cast<unsigned long long>(below),
        static_cast<unsigned long long>(stateHash(state.particles)), out_.empty() ? "" : ", wrote ",
        out_.c_str());
    return device ? finish(*device, 0) : 0;
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
