// `lava bench`: updates per second of each backend against the roofline of a copy kernel
// moving the bytes of one step, on the same device in the same run.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <sstream>
#include <thread>

#include "commands.h"
#include "host/output.h"
#include "lava/lava.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

struct Row {
  std::string backend;
  uint64_t particles;
  uint64_t steps;
  double updatesPerSecond;        // end to end, wall clock
  double deviceUpdatesPerSecond;  // GPU: timestamp queries; CPU: same as end to end
  double copyGbps;                // the roofline kernel's bandwidth
  double rooflineFraction;        // device updates/s over copy bandwidth / bytes per update
};

double secondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class BenchCommand final : public Command {
 public:
  explicit BenchCommand(CLI::App& app)
      : Command(
            app.add_subcommand("bench", "updates/s of gpu, cpu and cpu-mt against the roofline")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "sizes", "comma-separated particle counts [65536,262144,1048576,4194304]",
        [this](const std::string& src, const std::string& t) { sizes_ = parseSizes(src, t); });
    options_.add("steps", "steps timed per size and backend, 1..100000 [200]",
                 [this](const std::string& src, const std::string& t) {
                   steps_ = parseInteger(src, t, 1, 100000);
                 });
    options_.add("steps-per-dispatch",
                 "GPU steps fused per dispatch, 1..256 [256]; 1 is the unfused, memory-bound step",
                 [this](const std::string& src, const std::string& t) {
                   fused_ = static_cast<uint32_t>(parseInteger(src, t, 1, 256));
                 });
    options_.add("backends", "comma-separated subset of gpu,cpu,cpu-mt [all]",
                 [this](const std::string& src, const std::string& t) {
                   backends_ = parseBackends(src, t);
                 });
    options_.add("json", "also write the results to FILE.json",
                 [this](const std::string& src, const std::string& t) {
                   host::checkOutputPath(src, t, ".json");
                   json_ = t;
                 });
  }

  int run() override {
    options_.resolve();
    if (options_.given("particles"))
      throw host::UsageError("--particles: bench sets the counts with --sizes (e.g. --sizes " +
                             options_.text("particles") + ")");
    Device context(deviceOptions(device_));
    const std::string device = context.properties().deviceName;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    std::printf("bench: %s, %llu steps, %u steps per dispatch, %u CPU threads for cpu-mt\n",
                device.c_str(), static_cast<unsigned long long>(steps_), fused_, cores);
    std::printf("%-7s %10s %16s %16s %9s %10s %9s\n", "backend", "particles", "updates/s",
                "device upd/s", "GB/s", "copy GB/s", "x copy");
    std::vector<Row> rows;
    for (uint32_t n : sizes_) {
      if (n > context.maxParticles())
        throw host::UsageError("--sizes: " + std::to_string(n) +
                               " particles exceed this device's " +
                               std::to_string(context.maxParticles()) + " (see 'lava info')");
      Scene scene = scene_;
      scene.emitters.at(0).particles = n;
      const State start = allAlive(scene);
      if (wants("gpu")) rows.push_back(benchGpu(context, scene, start));
      if (wants("cpu")) rows.push_back(benchCpu(scene, start, 1, "cpu"));
      if (wants("cpu-mt")) rows.push_back(benchCpu(scene, start, cores, "cpu-mt"));
    }
    std::printf(
        "x copy: bytes the backend moved per second (64 per update) over the copy kernel's "
        "bandwidth on the same device; above 1, fused steps keep particles in registers and "
        "the step is bound by compute, not memory\n");
    if (!json_.empty()) host::writeFileAtomically(json_, toJson(device, rows));
    return finish(context, 0);
  }

 private:
  bool wants(const std::string& backend) const {
    return backends_.empty() ||
           std::find(backends_.begin(), backends_.end(), backend) != backends_.end();
  }

  // Every slot alive: one step of an emission rate that fills the whole ring.
  static State allAlive(const Scene& scene) {
    Scene fill = scene;
    fill.emitters.at(0).burst = fill.emitters.at(0).particles;
    CpuSimulation sim(fill, std::max(1u, std::thread::hardware_concurrency()));
    sim.advance(1);
    return sim.state();
  }

  Row benchGpu(Device& context, const Scene& scene, const State& start) {
    GpuSimulationOptions options;
    options.stepsPerDispatch = fused_;
    GpuSimulation sim(context, scene, options);
    sim.setState(start);
    sim.advance(std::min<uint64_t>(steps_, 64));  // warm-up
    double device = 0.0;
    const double wall = secondsOf([&] { device = sim.advanceTimed(steps_); });
    const double copy = gpuCopySeconds(context, scene.particles());
    return report({"gpu", scene.particles(), steps_, updates(scene, wall), updates(scene, device),
                   bandwidth(scene, copy), 0.0});
  }

  Row benchCpu(const Scene& scene, const State& start, unsigned threads, const char* name) {
    CpuSimulation sim(scene, threads);
    sim.setState(start);
    sim.advance(std::min<uint64_t>(steps_, 16));  // warm-up
    const double wall = secondsOf([&] { sim.advance(steps_); });
    const double copy = cpuCopySeconds(scene.particles(), threads);
    return report({name, scene.particles(), steps_, updates(scene, wall), updates(scene, wall),
                   bandwidth(scene, copy), 0.0});
  }

  double updates(const Scene& scene, double seconds) const {
    return double(scene.particles()) * double(steps_) / seconds;
  }
  static double bandwidth(const Scene& scene, double copySeconds) {
    return double(scene.particles()) * kBytesPerUpdate / copySeconds * 1e-9;
  }

  static Row report(Row row) {
    row.rooflineFraction = row.deviceUpdatesPerSecond * kBytesPerUpdate * 1e-9 / row.copyGbps;
    std::printf("%-7s %10llu %16.4g %16.4g %9.2f %10.2f %8.2fx\n", row.backend.c_str(),
                static_cast<unsigned long long>(row.particles), row.updatesPerSecond,
                row.deviceUpdatesPerSecond, row.deviceUpdatesPerSecond * kBytesPerUpdate * 1e-9,
                row.copyGbps, row.rooflineFraction);
    std::fflush(stdout);
    return row;
  }

  std::string toJson(const std::string& device, const std::vector<Row>& rows) const {
    std::ostringstream out;
    out.precision(6);
    out << "{\n  \"device\": \"" << device << "\",\n  \"steps_per_dispatch\": " << fused_
        << ",\n  \"results\": [\n";
    for (size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      out << "    {\"backend\": \"" << r.backend << "\", \"device\": \""
          << (r.backend == "gpu" ? device : std::string("host CPU"))
          << "\", \"particles\": " << r.particles << ", \"steps\": " << r.steps
          << ", \"updates_per_second\": " << r.updatesPerSecond
          << ", \"device_updates_per_second\": " << r.deviceUpdatesPerSecond
          << ", \"bytes_per_update\": " << kBytesPerUpdate << ", \"copy_gbps\": " << r.copyGbps
          << ", \"roofline_fraction\": " << r.rooflineFraction << "}"
          << (i + 1 < rows.size() ? "," : "") << "\n";
    }
    out << "  ]\n}\n";
    return out.str();
  }

  static std::vector<uint32_t> parseSizes(const std::string& source, const std::string& text) {
    std::vector<uint32_t> sizes;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');)
      sizes.push_back(static_cast<uint32_t>(parseInteger(source, item, 1, 0x80000000u)));
    if (sizes.empty() || text.back() == ',')
      throw host::UsageError(source + ": expected comma-separated particle counts, got '" + text +
                             "'");
    return sizes;
  }

  static std::vector<std::string> parseBackends(const std::string& source,
                                                const std::string& text) {
    std::vector<std::string> backends;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');) {
      if (item != "gpu" && item != "cpu" && item != "cpu-mt")
        throw host::UsageError(
            source + ": expected a comma-separated subset of gpu,cpu,cpu-mt, got '" + text + "'");
      backends.push_back(item);
    }
    if (backends.empty())
      throw host::UsageError(source + ": expected at least one of gpu,cpu,cpu-mt");
    return backends;
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  std::vector<uint32_t> sizes_{65536, 262144, 1048576, 4194304};
  uint64_t steps_ = 200;
  uint32_t fused_ = 256;
  std::vector<std::string> backends_;
  std::string json_;
};

}  // namespace

std::unique_ptr<Command> makeBench(CLI::App& app) {
  return std::make_unique<BenchCommand>(app);
}

}  // namespace lava::app
