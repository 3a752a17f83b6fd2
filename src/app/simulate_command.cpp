// `lava simulate`: runs a scene on the GPU or the CPU reference and writes the final state;
// checkpoints it (at the end, every K steps, and on SIGINT/SIGTERM) and resumes from one.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include "commands.h"
#include "host/output.h"
#include "host/series.h"
#include "lava/checkpoint.h"
#include "lava/lava.h"
#include "options.h"
#include "paths.h"
#include "resume.h"
#include "runtime.h"

namespace lava::app {
namespace {

volatile std::sig_atomic_t interrupted = 0;  // the signal that asked the run to stop

extern "C" void onStopSignal(int signal) {
  interrupted = signal;
}

class SimulateCommand final : public Command {
 public:
  explicit SimulateCommand(CLI::App& app)
      : Command(app, "simulate", "run a scene headless and write its final state"),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.addInteger("steps", "steps to run, 0..1e9 (required)", steps_, 0, 1000000000, true);
    addBackendFlags(options_, backend_);
    options_.add("out", "write the final state to FILE.npy or FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkStatePath(src, t);
                   out_ = t;
                 });
    options_.add("checkpoint",
                 "write the run's state and scene to FILE.npz at the end, every "
                 "--checkpoint-every steps, and on SIGINT/SIGTERM (then exit 130/143)",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".npz");
                   checkpoint_ = t;
                 });
    options_.addInteger("checkpoint-every",
                        "with --checkpoint: also every K steps, 1..1e9 [at the end]", every_, 1,
                        1000000000);
    addSeriesFlags(options_, series_, seriesEvery_);
    options_.add("resume",
                 "continue the run a checkpoint FILE.npz holds: its scene (scene flags may "
                 "change its parameters, not its emitters or their capacities) and state; "
                 "--steps more steps",
                 [](const std::string&, const std::string&) {});  // read before resolve()
  }

  int run() override {
    const auto begun = std::chrono::steady_clock::now();
    const std::optional<Snapshot> resumed = readResume(options_, scene_);
    options_.resolve();
    if (every_ && checkpoint_.empty())
      throw UsageError("--checkpoint-every: needs --checkpoint FILE.npz");
    checkSeriesFlags(series_, seriesEvery_);
    if (resumed) checkResumedScene(scene_, resumed->scene);
    std::unique_ptr<Device> device;
    const std::unique_ptr<Simulation> simulation = makeSimulation(device);
    if (resumed) simulation->setState(resumed->state);
    std::optional<host::SeriesWriter> series;
    if (!series_.empty())
      series.emplace(openSeries(resumed ? resumed->state.step : 0, resumed.has_value()));
    interrupted = 0;
    using Handler = void (*)(int);
    Handler previousInt = SIG_DFL, previousTerm = SIG_DFL;  // the program's: say and exit
    const bool stopAtAStep = !checkpoint_.empty() || series;
    if (stopAtAStep) {  // instead: the checkpoint at the next step boundary
      previousInt = std::signal(SIGINT, onStopSignal);
      previousTerm = std::signal(SIGTERM, onStopSignal);
    }

    const auto start = std::chrono::steady_clock::now();
    const uint64_t done =
        advance(*simulation, resumed ? resumed->state.step : 0, series ? &*series : nullptr);
    if (stopAtAStep) {
      std::signal(SIGINT, previousInt);
      std::signal(SIGTERM, previousTerm);
    }
    if (interrupted) {
      reportInterrupt(*simulation, done, series ? &*series : nullptr);
      const int status = interrupted == SIGINT ? 130 : 143;
      return device ? finish(*device, status) : status;
    }
    const State state = checkpoint_.empty() ? simulation->state() : saveCheckpoint(*simulation);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!out_.empty()) host::writeState(out_, state);
    report(state, simulation->name(), seconds, std::chrono::duration<double>(start - begun).count(),
           series ? &*series : nullptr);
    return device ? finish(*device, 0) : 0;
  }

 private:
  // The simulation --backend names; a GPU one's device goes to `device`.
  std::unique_ptr<Simulation> makeSimulation(std::unique_ptr<Device>& device) const {
    if (backend_.gpu) {
      device = std::make_unique<Device>(deviceOptions(device_));
      return std::make_unique<GpuSimulation>(*device, scene_);
    }
    return std::make_unique<CpuSimulation>(scene_, backend_.cpuThreads(), backend_.kernel);
  }

  // The finished run's summary: the final state's counts and hash, then the files written.
  void report(const State& state, const std::string& simulation, double seconds,
              double setupSeconds, const host::SeriesWriter* series) const {
    uint64_t alive = 0, below = 0;
    for (const Particle& p : state.particles) {
      alive += p.age >= 0.0f;
      below += p.age >= 0.0f && p.py < 0.0f;
    }
    std::printf(
        "simulate: %llu particles x %llu steps on %s in %s (and %s to set up): %llu alive, "
        "%llu below ground, "
        "state hash %016llx%s%s\n",
        static_cast<unsigned long long>(scene_.particles()),
        static_cast<unsigned long long>(steps_), simulation.c_str(), formatSeconds(seconds).c_str(),
        formatSeconds(setupSeconds).c_str(), static_cast<unsigned long long>(alive),
        static_cast<unsigned long long>(below), static_cast<unsigned long long>(stateHash(state)),
        out_.empty() ? "" : ", wrote ", out_.c_str());
    if (!checkpoint_.empty())
      std::printf("simulate: checkpoint at step %llu in %s\n",
                  static_cast<unsigned long long>(state.step), checkpoint_.c_str());
    if (series)
      std::printf("simulate: series of %zu samples in %s\n", series->samples(),
                  series->collection().c_str());
  }

  // --steps steps, or fewer when a signal stops the run at a step boundary; the steps done.
  uint64_t advance(Simulation& simulation, uint64_t first, host::SeriesWriter* series) {
    // Batches of about 2^26 particle-steps (at least one step, at most 4096): a signal is
    // answered within a fraction of a second, at a step boundary.
    const uint64_t batchSteps = std::clamp<uint64_t>(
        (uint64_t{1} << 26) / std::max<uint64_t>(scene_.particles(), 1), 1, 4096);
    if (series && series->due(first)) writeSample(*series, simulation.state());
    uint64_t done = 0;
    Progress progress("simulate", steps_);
    while (done < steps_ && !interrupted) {
      uint64_t batch = std::min<uint64_t>(steps_ - done, batchSteps);
      if (every_) batch = std::min<uint64_t>(batch, every_ - done % every_);
      if (series) batch = std::min<uint64_t>(batch, seriesEvery_ - (first + done) % seriesEvery_);
      simulation.advance(batch);
      done += batch;
      progress.update(done);
      if (every_ && done % every_ == 0 && done < steps_) saveCheckpoint(simulation);
      if (series && series->due(first + done)) writeSample(*series, simulation.state());
    }
    return done;
  }

  void reportInterrupt(Simulation& simulation, uint64_t done, const host::SeriesWriter* series) {
    const char* signal = interrupted == SIGINT ? "SIGINT" : "SIGTERM";
    const auto left = static_cast<unsigned long long>(steps_ - done);
    if (checkpoint_.empty()) {
      std::printf("simulate: interrupted by %s after %llu of %llu steps; %s names the %zu "
                  "samples written (without --checkpoint the run cannot be resumed)\n",
                  signal, static_cast<unsigned long long>(done),
                  static_cast<unsigned long long>(steps_), series->collection().c_str(),
                  series->samples());
      return;
    }
    const State state = saveCheckpoint(simulation);
    std::printf(
        "simulate: interrupted by %s after %llu of %llu steps (step %llu of the run); wrote "
        "%s: continue with lava simulate --resume %s --steps %llu%s\n",
        signal, static_cast<unsigned long long>(done), static_cast<unsigned long long>(steps_),
        static_cast<unsigned long long>(state.step), checkpoint_.c_str(), checkpoint_.c_str(),
        left, series ? (" --series " + series_ + " --every " + std::to_string(seriesEvery_)).c_str()
                     : "");
  }

  host::SeriesWriter openSeries(uint64_t firstStep, bool resumed) const {
    try {
      return host::SeriesWriter(series_, seriesEvery_, firstStep, resumed);
    } catch (const std::exception& e) {
      throw UsageError("--series: " + std::string(e.what()));
    }
  }

  void writeSample(host::SeriesWriter& series, const State& state) const {
    try {
      series.write(scene_, state);
    } catch (const ResourceError& e) {
      throw UsageError("--series: " + std::string(e.what()));
    }
  }

  // The state now, written to --checkpoint.
  State saveCheckpoint(Simulation& simulation) const {
    State state = simulation.state();
    try {
      writeCheckpoint(checkpoint_, scene_, state);
    } catch (const ResourceError& e) {
      throw UsageError("--checkpoint: " + std::string(e.what()));
    }
    return state;
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  uint64_t steps_ = 0;
  BackendChoice backend_;
  std::string out_;
  std::string checkpoint_;
  uint64_t every_ = 0;
  std::string series_;
  uint64_t seriesEvery_ = 0;
};

}  // namespace

std::unique_ptr<Command> makeSimulate(CLI::App& app) {
  return std::make_unique<SimulateCommand>(app);
}

}  // namespace lava::app
