// `lava bench`: updates per second of each backend against two ceilings measured on the
// same device in the same run: a copy kernel moving the bytes of one step, and (CPU
// backends) the same kernel's step alone on particles that never leave L1.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "commands.h"
#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "host/output.h"
#include "lava/bench.h"
#include "lava/lava.h"
#include "options.h"
#include "paths.h"
#include "resume.h"
#include "runtime.h"

namespace lava::app {
namespace {

constexpr const char* kBackends = "gpu,cpu,cpu-mt,cpu-simd,cpu-simd-mt";

struct Row {
  std::string backend;
  uint64_t particles;
  uint64_t steps;
  double updatesPerSecond;         // end to end, wall clock
  double deviceUpdatesPerSecond;   // GPU: timestamp queries; CPU: same as end to end
  double copyGbps;                 // the roofline kernel's bandwidth
  double rooflineFraction;         // device updates/s over copy bandwidth / bytes per update
  uint64_t fused;                  // steps each particle takes per trip through memory
  double computeUpdatesPerSecond;  // the step alone, no memory traffic
  double computeFraction;          // device updates/s over that
  const char* bound;               // the lower ceiling: "compute", "memory" or "-"
};

double secondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class BenchCommand final : public Command {
 public:
  explicit BenchCommand(CLI::App& app)
      : Command(app, "bench",
                "updates/s of each backend against its copy and compute "
                "rooflines"),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add("sizes", "comma-separated particle counts [65536,262144,1048576,4194304]",
        [this](const std::string& src, const std::string& t) { sizes_ = parseSizes(src, t); });
    options_.addInteger("steps", "steps timed per size and backend, 1..100000 [200]", steps_, 1,
                        100000);
    options_.addInteger(
        "steps-per-dispatch",
        "GPU steps fused per dispatch, 1..256 [256]; 1 is the unfused, memory-bound step", fused_,
        1, 256);
    options_.add("backends", "comma-separated subset of " + std::string(kBackends) + " [all]",
                 [this](const std::string& src, const std::string& t) {
                   backends_ = parseBackends(src, t);
                 });
    options_.add("simd-target",
                 "instruction set of the cpu-simd rows, one of this CPU's (see 'lava info') "
                 "[the best]",
                 [this](const std::string& src, const std::string& t) {
                   try {
                     cpuSimdTarget(t);  // a name this CPU runs
                   } catch (const InvalidArgument& e) {
                     throw UsageError(src + ": " + e.detail());
                   }
                   simdTarget_ = t;
                 });
    options_.addFlag("flow",
                     "the flow's rows instead (backends gpu, cpu, cpu-mt): a slab of --sizes flow "
                     "particles at rest [4096,16384], its particle-steps/s, neighbour pairs/s "
                     "and their fraction of the density sum alone over lists made beforehand",
                     flow_);
    options_.add("resume",
                 "with --flow: the run a checkpoint FILE.npz holds (lava simulate "
                 "--checkpoint), from its state and in its scene, instead of a slab: the "
                 "eruption at a minute, say, sparks and all",
                 [](const std::string&, const std::string&) {});  // read before resolve()
    options_.addFlag("point",
                     "with --flow: every particle at one point at rest instead, a point "
                     "burst's first steps (the grid's worst case: one bucket)",
                     point_);
    options_.addFlag("draw",
                     "with --flow: the slab drawn instead, at 1280x720 in the lava look on the "
                     "Vulkan device: ms a frame with it and with its slots empty (the molten "
                     "surface's cost is the difference), medians of alternating frames",
                     draw_);
    options_.add("json", "also write the results to FILE.json",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".json");
                   json_ = t;
                 });
  }

  int run() override {
    resumed_ = readResume(options_, scene_);
    options_.resolve();
    if (resumed_) {
      checkResumedScene(scene_, resumed_->scene);
      if (!flow_ || draw_ || point_ || options_.given("sizes"))
        throw UsageError("--resume: needs --flow, without --draw, --point or --sizes (the "
                         "checkpoint's run is the one measured)");
    }
    if (point_ && !flow_) throw UsageError("--point: needs --flow (the flow's point burst)");
    if (draw_ && !flow_) throw UsageError("--draw: needs --flow (the flow's slab, drawn)");
    if (options_.given("particles"))
      throw UsageError("--particles: bench sets the counts with --sizes (e.g. --sizes " +
                       options_.text("particles") + ")");
    Device context(deviceOptions(device_));
    const std::string device = context.properties().deviceName;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    if (draw_) return runDraw(context, device);
    if (flow_) return runFlow(context, device, cores);
    std::printf(
        "bench: %s, %llu steps, %u steps per dispatch, %u CPU threads for -mt; "
        "cpu-simd: %s\n",
        device.c_str(), static_cast<unsigned long long>(steps_), fused_, cores,
        cpuSimdTarget(simdTarget_).c_str());
    std::printf("%-11s %10s %12s %12s %8s %9s %7s %12s %9s %7s\n", "backend", "particles",
                "updates/s", "device upd/s", "GB/s", "copy GB/s", "x copy", "compute upd/s",
                "x compute", "bound");
    std::vector<Row> rows;
    size_t kinds = 0;
    for (const char* b : {"gpu", "cpu", "cpu-mt", "cpu-simd", "cpu-simd-mt"}) kinds += wants(b);
    Progress progress("bench", sizes_.size() * kinds);
    progress_ = &progress;
    for (uint32_t n : sizes_) {
      if (n > context.maxParticles())
        throw UsageError("--sizes: " + std::to_string(n) + " particles exceed this device's " +
                         std::to_string(context.maxParticles()) + " (see 'lava info')");
      Scene scene = scene_;
      scene.emitters.at(0).particles = n;
      const State start = allAlive(scene);
      if (wants("gpu")) rows.push_back(benchGpu(context, scene, start));
      if (wants("cpu")) rows.push_back(benchCpu(scene, start, 1, CpuKernel::Reference, "cpu"));
      if (wants("cpu-mt"))
        rows.push_back(benchCpu(scene, start, cores, CpuKernel::Reference, "cpu-mt"));
      if (wants("cpu-simd")) rows.push_back(benchCpu(scene, start, 1, CpuKernel::Simd, "cpu-simd"));
      if (wants("cpu-simd-mt"))
        rows.push_back(benchCpu(scene, start, cores, CpuKernel::Simd, "cpu-simd-mt"));
    }
    progress.clear();
    progress_ = nullptr;
    std::printf(
        "x copy: bytes the backend moved per second (64 per update) over the copy kernel's "
        "bandwidth on the same device; above 1, fused steps keep particles in registers or "
        "L1 between trips through memory\n"
        "x compute: updates/s over the same kernel's steps alone, with no emission and no "
        "memory traffic (CPU: blocks that never leave L1; GPU: one read and write per run); "
        "bound: the lower ceiling, copy bandwidth x steps per trip through memory / "
        "64 B, or compute\n");
    if (!json_.empty()) host::writeFileAtomically(json_, toJson(device, rows));
    return finish(context, 0);
  }

 private:
  // A slab of n flow particles at rest on the ground, four layers deep on the rest lattice,
  // hot and never cooling: every particle with its full set of neighbours (or a surface's).
  static std::pair<Scene, State> flowSlab(const Scene& base, uint32_t n, bool point) {
    Scene scene = base;
    if (!scene.flow) scene.flow.emplace();
    scene.flow->coolingAir = 0.0f;
    scene.flow->coolingGround = 0.0f;
    scene.emitters.resize(1);
    scene.colliders.clear();  // the slab lies on the ground alone: a scene's cone would hold it
    Emitter& e = scene.emitters[0];
    e.particles = n;
    e.rate = 0.0;
    e.burst = 0;
    e.flow = true;
    e.temperature = 0.0f;
    const float s = 0.5f * scene.flow->radius;
    e.mass = scene.flow->density * s * s * s;
    checkScene(scene);
    State state = initialState(scene);
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(n) / 4.0)));
    for (uint32_t i = 0; i < n && point; ++i) {  // all at 1 m above the ground
      state.particles[i] = Particle{0.0f, 1.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, e.mass};
      state.temperature[i] = scene.flow->temperature;
    }
    for (uint32_t i = 0; i < n && !point; ++i) {
      const float x = (float(i % side) - 0.5f * float(side)) * s;
      const float z = (float(i / side % side) - 0.5f * float(side)) * s;
      const float y = (0.5f + float(i / (side * side))) * s;
      state.particles[i] = Particle{x, y, z, 1.0f, 0.0f, 0.0f, 0.0f, e.mass};
      state.temperature[i] = scene.flow->temperature;
    }
    return {scene, state};
  }

  int runFlow(Device& context, const std::string& device, unsigned cores) {
    const std::vector<uint32_t> sizes =
        options_.given("sizes") ? sizes_ : std::vector<uint32_t>{4096, 16384};
    // The implicit flow has no shader yet: the GPU backend steps it on the host, so its rows
    // are the CPU's unless --backends names the GPU (whose row then times the host's steps).
    const bool implicit = scene_.flow && scene_.flow->solver == FlowSolver::Implicit;
    const bool gpuRow = wants("gpu") && !(implicit && backends_.empty());
    const std::string what = resumed_ ? "the run " + options_.text("resume") + " holds, from step " +
                                            std::to_string(resumed_->state.step)
                           : point_ ? "a point burst" : "a slab at rest";
    std::printf("bench --flow: %s, %s, %s solver, dt %g s, %llu steps, %u CPU threads for "
                "cpu-mt%s\n",
                what.c_str(), device.c_str(),
                implicit ? "implicit" : "explicit", double(scene_.h()),
                static_cast<unsigned long long>(steps_), cores,
                implicit && !gpuRow ? " (no gpu row: the GPU backend steps the implicit flow on the host)"
                                     : "");
    std::printf("%-8s %10s %13s %9s %14s %14s %9s %11s\n", "backend", "particles",
                "particle-st/s", "pairs/st", "pairs/s", "ceiling pr/s", "x ceiling",
                "x real time");
    std::ostringstream json;
    json << "{\n  \"device\": \"" << device << "\",\n  \"flow\": [\n";
    bool first = true;
    if (resumed_)
      benchFlow(context, scene_, resumed_->state, gpuRow, cores, json, first);
    else
      for (uint32_t n : sizes) {
        const auto [scene, start] = flowSlab(scene_, n, point_);
        benchFlow(context, scene, start, gpuRow, cores, json, first);
      }
    std::printf(
        "pairs/st: neighbour pairs each step visits (both passes, counted at the start); "
        "ceiling: the density sum alone over neighbour lists made beforehand, on the same "
        "device (no grid, no sort, one pass); x real time: simulated seconds a second\n");
    json << "\n  ]\n}\n";
    if (!json_.empty()) host::writeFileAtomically(json_, json.str());
    return finish(context, 0);
  }

  // --flow --draw: per size, the slab's frame and the empty frame, alternating, each the
  // median of 9 (after one of each to warm up), at 1280x720; the renderer as the demo picks.
  int runDraw(Device& context, const std::string& device) {
    const std::vector<uint32_t> sizes =
        options_.given("sizes") ? sizes_ : std::vector<uint32_t>{16384, 262144};
    std::printf("bench --flow --draw: %s, a slab at rest at 1280x720, the lava look\n",
                device.c_str());
    std::printf("%10s %9s %12s %12s %12s\n", "particles", "renderer", "frame ms", "empty ms",
                "surface ms");
    std::ostringstream json;
    json << "{\n  \"device\": \"" << device << "\",\n  \"draw\": [\n";
    const OrbitCamera camera;
    const host::OffscreenTarget target(context, {1280, 720});
    for (size_t row = 0; row < sizes.size(); ++row) {
      const uint32_t n = sizes[row];
      auto [scene, full] = flowSlab(scene_, n, point_);
      State empty = full;
      for (size_t i = 0; i < empty.particles.size(); ++i) {
        empty.particles[i].age = -1.0f;
        empty.temperature[i] = 0.0f;
      }
      GpuSimulation sim(context, scene);
      host::FrameRenderer renderer(context, host::OffscreenTarget::kColorFormat);
      const LineMode mode = n >= kSplatFrom ? LineMode::Splat : LineMode::Lines;
      renderer.setLineMode(mode);
      std::vector<double> times[2];
      for (int k = 0; k < 20; ++k) {
        const bool withSlab = k % 2 == 0;
        sim.setState(withSlab ? full : empty);
        const double seconds =
            secondsOf([&] { host::renderOffscreen(context, renderer, sim, target, camera); });
        if (k >= 2) times[withSlab ? 0 : 1].push_back(seconds * 1e3);
      }
      for (std::vector<double>& t : times) std::sort(t.begin(), t.end());
      const double frame = times[0][times[0].size() / 2], none = times[1][times[1].size() / 2];
      const char* name = mode == LineMode::Splat ? "splat" : "lines";
      std::printf("%10u %9s %12.2f %12.2f %12.2f\n", n, name, frame, none, frame - none);
      json << (row == 0 ? "" : ",\n") << "    {\"particles\": " << n
           << ", \"renderer\": \"" << name << "\", \"frame_ms\": " << frame
           << ", \"empty_ms\": " << none << "}";
    }
    std::printf("frame: the slab drawn, read back included; empty: the same slots unborn\n");
    json << "\n  ]\n}\n";
    if (!json_.empty()) host::writeFileAtomically(json_, json.str());
    return finish(context, 0);
  }

  // The --flow rows of a scene from `start`, printed and appended to json (`first`: no comma
  // before); its particles are the flow particles alive at the start.
  void benchFlow(Device& context, const Scene& scene, const State& start, bool gpuRow,
                 unsigned cores, std::ostringstream& json, bool& first) {
    const FlowNeighbours neighbours = flowNeighbours(scene, start);
    const uint32_t n = uint32_t(neighbours.particles.size());
    // Both neighbour passes visit every pair, per step.
    const double pairs = 2.0 * double(neighbours.lists.size());
    const auto row = [&](const char* backend, double seconds, double ceiling) {
      const double steps = double(steps_);
      const double pairsPerSecond = pairs * steps / seconds;
      // Simulated seconds per wall second: 1 is real time.
      const double realTime = steps * double(scene_.h()) / seconds;  // the slab's dt
      std::printf("%-8s %10u %13.4g %9.1f %14.4g %14.4g %9.3f %11.4g\n", backend, n,
                  double(n) * steps / seconds, pairs / double(n), pairsPerSecond, ceiling,
                  pairsPerSecond / ceiling, realTime);
      json << (first ? "" : ",\n") << "    {\"backend\": \"" << backend
           << "\", \"particles\": " << n
           << ", \"particle_steps_per_second\": " << double(n) * steps / seconds
           << ", \"pairs_per_second\": " << pairsPerSecond
           << ", \"ceiling_pairs_per_second\": " << ceiling
           << ", \"real_time_factor\": " << realTime << "}";
      first = false;
    };
    if (gpuRow) {
      GpuSimulation sim(context, scene);
      sim.setState(start);
      sim.advance(std::min<uint64_t>(steps_, 16));  // warm-up
      sim.setState(start);
      // The implicit flow is stepped on the host: wall time, not the device's timestamps.
      const bool onHost = scene.flow->solver == FlowSolver::Implicit;
      const double seconds =
          onHost ? secondsOf([&] { sim.advance(steps_); }) : sim.advanceTimed(steps_);
      row("gpu", seconds, gpuFlowPairsPerSecond(context, scene, neighbours));
    }
    for (const auto& [name, threads] :
         {std::pair<const char*, unsigned>{"cpu", 1u}, {"cpu-mt", cores}}) {
      if (!wants(name)) continue;
      CpuSimulation sim(scene, threads);
      sim.setState(start);
      const double seconds = secondsOf([&] { sim.advance(steps_); });
      row(name, seconds, cpuFlowPairsPerSecond(scene, neighbours, threads));
    }
  }

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
    const double compute = gpuComputeUpdatesPerSecond(
        context, scene, start.particles, static_cast<uint32_t>(std::max<uint64_t>(steps_, 64)));
    return report({"gpu", scene.particles(), steps_, updates(scene, wall), updates(scene, device),
                   bandwidth(scene, copy), 0.0, std::min<uint64_t>(steps_, fused_), compute, 0.0,
                   "-"});
  }

  Row benchCpu(const Scene& scene, const State& start, unsigned threads, CpuKernel kernel,
               const char* name) {
    CpuSimulation sim(scene, threads, kernel, simdTarget_);
    sim.setState(start);
    sim.advance(std::min<uint64_t>(steps_, 16));  // warm-up
    const double wall = secondsOf([&] { sim.advance(steps_); });
    const double copy = cpuCopySeconds(scene.particles(), threads);
    // The compute ceiling does not depend on the particle count: measured once per row kind.
    auto [ceiling, fresh] = computeCeilings_.try_emplace(name, 0.0);
    if (fresh)
      ceiling->second = cpuComputeUpdatesPerSecond(scene, start.particles, steps_, threads, kernel,
                                                   3, 0.15, simdTarget_);
    // A block stays in L1 for a whole batch of planned steps (4096 at most).
    return report({name, scene.particles(), steps_, updates(scene, wall), updates(scene, wall),
                   bandwidth(scene, copy), 0.0, std::min<uint64_t>(steps_, 4096), ceiling->second,
                   0.0, "-"});
  }

  double updates(const Scene& scene, double seconds) const {
    return double(scene.particles()) * double(steps_) / seconds;
  }
  static double bandwidth(const Scene& scene, double copySeconds) {
    return double(scene.particles()) * kBytesPerUpdate / copySeconds * 1e-9;
  }

  Row report(Row row) {
    if (progress_) progress_->clear();
    row.rooflineFraction = row.deviceUpdatesPerSecond * kBytesPerUpdate * 1e-9 / row.copyGbps;
    const double memoryCeiling = row.copyGbps * 1e9 / kBytesPerUpdate * double(row.fused);
    char compute[32] = "-", fraction[32] = "-";
    if (row.computeUpdatesPerSecond > 0.0) {
      row.computeFraction = row.deviceUpdatesPerSecond / row.computeUpdatesPerSecond;
      row.bound = row.computeUpdatesPerSecond < memoryCeiling ? "compute" : "memory";
      std::snprintf(compute, sizeof(compute), "%.4g", row.computeUpdatesPerSecond);
      std::snprintf(fraction, sizeof(fraction), "%.2f", row.computeFraction);
    } else if (row.fused == 1) {
      row.bound = "memory";  // one step per trip: the copy ceiling is the step's own
    }
    std::printf("%-11s %10llu %12.4g %12.4g %8.2f %9.2f %6.2fx %12s %9s %7s\n", row.backend.c_str(),
                static_cast<unsigned long long>(row.particles), row.updatesPerSecond,
                row.deviceUpdatesPerSecond, row.deviceUpdatesPerSecond * kBytesPerUpdate * 1e-9,
                row.copyGbps, row.rooflineFraction, compute, fraction, row.bound);
    std::fflush(stdout);
    if (progress_) progress_->update(++reported_);
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
          << ", \"roofline_fraction\": " << r.rooflineFraction
          << ", \"steps_per_memory_trip\": " << r.fused
          << ", \"compute_updates_per_second\": " << r.computeUpdatesPerSecond
          << ", \"compute_fraction\": " << r.computeFraction << ", \"bound\": \"" << r.bound
          << "\"}" << (i + 1 < rows.size() ? "," : "") << "\n";
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
      throw UsageError(source + ": expected comma-separated particle counts, got '" + text + "'");
    return sizes;
  }

  static std::vector<std::string> parseBackends(const std::string& source,
                                                const std::string& text) {
    std::vector<std::string> backends;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');) {
      if (item != "gpu" && item != "cpu" && item != "cpu-mt" && item != "cpu-simd" &&
          item != "cpu-simd-mt")
        throw UsageError(source + ": expected a comma-separated subset of " + kBackends +
                         ", got '" + text + "'");
      backends.push_back(item);
    }
    if (backends.empty())
      throw UsageError(source + ": expected at least one of " + std::string(kBackends));
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
  bool flow_ = false;
  std::optional<Snapshot> resumed_;                // --resume
  bool point_ = false;                             // --point
  bool draw_ = false;                              // --draw
  std::string simdTarget_;                         // --simd-target ("": the best)
  std::map<std::string, double> computeCeilings_;  // per row kind
  Progress* progress_ = nullptr;                   // rows done, while run() runs
  uint64_t reported_ = 0;
};

}  // namespace

std::unique_ptr<Command> makeBench(CLI::App& app) {
  return std::make_unique<BenchCommand>(app);
}

}  // namespace lava::app
