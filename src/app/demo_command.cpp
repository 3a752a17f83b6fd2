// `lava demo`: the interactive window; with no display (or --headless) the same scene is
// rendered offscreen into PNG frames instead, and the command says where they are.
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>

#include "commands.h"
#include "frames.h"
#include "host/output.h"
#include "lava/device.h"
#include "options.h"
#include "paths.h"
#include "resume.h"
#include "runtime.h"
#include "window/demo_window.h"

namespace lava::app {
namespace {

// On a CPU device, llvmpipe (lavapipe) hands each of its threads one contiguous share of a
// dispatch's workgroups, fixed in advance. The splat's work is uneven along the ring (young,
// fast lava draws long lines; landed lava one pixel), so one thread finishes its share early
// and its core idles while the other draws the rest. With two threads per core the system's
// scheduler fills that core. Unless the user
// chose LP_NUM_THREADS, the demo sets it before any Vulkan call; returns the value it set,
// or 0. No other driver reads it.
unsigned oversubscribeCpuDevice() {
  if (std::getenv("LP_NUM_THREADS")) return 0;
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores == 0) return 0;
  const unsigned threads = 2 * cores;
  return setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 0) == 0 ? threads : 0;
}

// The line saying so, on a llvmpipe device.
void sayThreads(unsigned threads, const std::string& device) {
  if (threads && device.rfind("llvmpipe", 0) == 0)
    std::printf(
        "demo: LP_NUM_THREADS=%u (llvmpipe, two threads per core; set LP_NUM_THREADS "
        "to choose)\n",
        threads);
}

class DemoCommand final : public Command {
 public:
  explicit DemoCommand(CLI::App& app)
      : Command(app, "demo", "the interactive lava demo in a window"), options_(*command_) {
    options_.addSceneFlags(demo_.scene, demo_.device);
    options_.add(
        "size", "window size WxH [1280x720]",
        [this](const std::string& src, const std::string& t) { demo_.size = parseSize(src, t); });
    options_.addInteger(
        "frames",
        "exit after N frames with an average-fps line, 1..10000000 [until closed; 90 headless]",
        demo_.frames, 1, 10000000);
    options_.add(
        "renderer",
        "splat (compute) or lines (the graphics pipeline, the reference) "
        "[splat from 16384 particles, else lines]",
        [this](const std::string& src, const std::string& t) { lines_ = parseLineMode(src, t); });
    addLookFlags(options_, look_);
    options_.add("resume",
                 "start from the state a checkpoint FILE.npz holds (lava simulate "
                 "--checkpoint), in its scene; --warmup seconds more before the first frame",
                 [](const std::string&, const std::string&) {});  // read before resolve()
    options_.add("warmup", "seconds simulated before the first frame, 0..600 [0]",
                 [this](const std::string& src, const std::string& t) {
                   demo_.warmup = parseNumber(src, t, 0, 600);
                 });
    addBackendFlags(options_, backend_);
    options_.addFlag("headless", "render PNG frames offscreen instead of a window", headless_);
    options_.addFlag("vsync",
                     "present with FIFO (vsync) through the swapchain; default: fastest mode",
                     demo_.vsync);
    options_.add("present",
                 "swapchain (Vulkan presentation) or shm (X11 MIT-SHM, for CPU devices) "
                 "[shm on a CPU device when the X server allows, else swapchain]",
                 [this](const std::string& src, const std::string& t) {
                   demo_.present = window::parsePresentPath(src, t);
                 });
    options_.add(
        "out", "folder for headless frames [lava-demo-frames]",
        [this](const std::string& src, const std::string& t) { out_ = outputFolder(src, t); });
  }

  int run() override {
    std::optional<Snapshot> resumed = readResume(options_, demo_.scene);
    options_.resolve();
    if (resumed) {
      checkResumedScene(demo_.scene, resumed->scene);
      demo_.start = std::move(resumed->state);
    }
    const unsigned threads = oversubscribeCpuDevice();
    demo_.validation = validationRequested();
    if (!demo_.device) demo_.device = deviceOptions(demo_.device).index;
    demo_.style = look_.style;
    demo_.look = look_.settings;
    demo_.lines = lines_.value_or(defaultLineMode(demo_.scene.particles()));
    if (demo_.vsync && demo_.present == window::PresentPath::Shm)
      throw UsageError("--vsync: needs --present swapchain (MIT-SHM has no vsync)");
    chooseStepper();
    if (!headless_) {
      try {
        const window::DemoSummary s = window::runDemoWindow(demo_);
        char times[160];
        if (demo_.cpu)
          std::snprintf(times, sizeof(times), "GPU per frame: draw %.2f ms; %s steps: %.2f ms",
                        s.drawMs, backend_.kernel == CpuKernel::Simd ? "cpu-simd" : "cpu",
                        s.simulateMs);
        else
          std::snprintf(times, sizeof(times), "GPU per frame: simulate %.2f ms, draw %.2f ms",
                        s.simulateMs, s.drawMs);
        std::printf(
            "demo: %u frames in %.2f s, average %.1f fps (%ux%u, %llu particles, %s, %s; "
            "%s; CPU per frame %.2f ms)\n",
            s.frames, s.seconds, s.seconds > 0 ? s.frames / s.seconds : 0.0, s.size.width,
            s.size.height, static_cast<unsigned long long>(demo_.scene.particles()),
            s.device.c_str(), s.presentMode.c_str(), times,
            s.frames ? 1e3 * s.cpuSeconds / s.frames : 0.0);
        sayThreads(threads, s.device);
        return s.validationMessages ? 1 : 0;
      } catch (const window::NoDisplay& e) {
        std::printf("demo: %s; rendering headless instead\n", e.what());
      }
    }
    FramePlan plan;
    plan.frames = demo_.frames ? demo_.frames : 90;
    plan.size = demo_.size;
    plan.folder = outputFolder("--out", out_);
    plan.lines = demo_.lines;
    plan.look = look_;
    plan.warmup = demo_.warmup;
    plan.start = demo_.start;
    plan.backend = backend_;
    Device device(deviceOptions(demo_.device));
    const double seconds = renderFrames(device, demo_.scene, plan);
    std::printf(
        "demo: %u headless frames in %.2f s, average %.1f fps (%ux%u, %llu particles); "
        "wrote %s/frame_*.png\n",
        plan.frames, seconds, seconds > 0 ? plan.frames / seconds : 0.0, plan.size.width,
        plan.size.height, static_cast<unsigned long long>(demo_.scene.particles()),
        plan.folder.c_str());
    sayThreads(threads, device.properties().deviceName);
    return finish(device, 0);
  }

 private:
  // The CPU steps the run with --backend cpu or cpu-simd, and the implicit flow's unless
  // --backend says otherwise (it has no shader yet: the GPU backend would step it on the
  // host, beside the sparks); the device draws it.
  void chooseStepper() {
    const bool implicit = demo_.scene.flow && demo_.scene.flow->solver == FlowSolver::Implicit;
    const bool chosen = options_.given("backend");
    if (implicit && !chosen) backend_ = {false, CpuKernel::Simd, backend_.threads};
    if (backend_.gpu) return;
    demo_.cpu = host::FrameRun::CpuStepping{backend_.cpuThreads(), backend_.kernel};
    std::printf("demo: %s steps the run on %u thread%s%s, the device draws it\n",
                backend_.kernel == CpuKernel::Simd ? "cpu-simd" : "cpu", demo_.cpu->threads,
                demo_.cpu->threads == 1 ? "" : "s",
                chosen ? "" : " (the implicit flow has no GPU shader yet)");
  }

  Options options_;
  BackendChoice backend_;
  window::DemoOptions demo_;
  LookOptions look_;
  std::optional<LineMode> lines_;  // --renderer; unset: defaultLineMode
  bool headless_ = false;
  std::string out_ = "lava-demo-frames";
};

}  // namespace

std::unique_ptr<Command> makeDemo(CLI::App& app) {
  return std::make_unique<DemoCommand>(app);
}

}  // namespace lava::app
