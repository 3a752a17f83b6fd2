// `lava demo`: the interactive window; with no display (or --headless) the same scene is
// rendered offscreen into PNG frames instead, and the command says where they are.
#include <cstdio>
#include <optional>

#include "commands.h"
#include "demo_window.h"
#include "frames.h"
#include "options.h"
#include "runtime.h"
#include "vk_check.h"

namespace lava::app {
namespace {

class DemoCommand final : public Command {
 public:
  explicit DemoCommand(CLI::App& app)
      : Command(app.add_subcommand("demo", "the interactive lava demo in a window")),
        options_(*command_) {
    options_.addSceneFlags(demo_.scene, demo_.device);
    options_.add(
        "size", Kind::Text, "window size WxH [1280x720]",
        [this](const std::string& src, const std::string& t) { demo_.size = parseSize(src, t); });
    options_.add(
        "frames", Kind::Number,
        "exit after N frames with an average-fps line, 1..10000000 [until closed; 90 headless]",
        [this](const std::string& src, const std::string& t) {
          demo_.frames = static_cast<uint32_t>(parseInteger(src, t, 1, 10000000));
        });
    options_.add(
        "renderer", Kind::Text,
        "splat (compute) or lines (the graphics pipeline, the reference) "
        "[splat from 16384 particles, else lines]",
        [this](const std::string& src, const std::string& t) { lines_ = parseLineMode(src, t); });
    options_.add("warmup", Kind::Number, "seconds simulated before the first frame, 0..600 [0]",
                 [this](const std::string& src, const std::string& t) {
                   demo_.warmup = parseNumber(src, t, 0, 600);
                 });
    command_->add_flag("--headless", headless_, "render PNG frames offscreen instead of a window");
    command_->add_flag("--vsync", demo_.vsync,
                       "present with FIFO (vsync) through the swapchain; default: fastest mode");
    options_.add("present", Kind::Text,
                 "swapchain (Vulkan presentation) or shm (X11 MIT-SHM, for CPU devices) "
                 "[shm on a CPU device when the X server allows, else swapchain]",
                 [this](const std::string& src, const std::string& t) {
                   demo_.present = parsePresentPath(src, t);
                 });
    command_->add_flag("--exercise", demo_.exercise,
                       "resize, minimise and restore the window on a schedule (for tests)");
    options_.add(
        "out", Kind::Text, "folder for headless frames [lava-demo-frames]",
        [this](const std::string& src, const std::string& t) { out_ = outputFolder(src, t); });
  }

  int run() override {
    options_.resolve();
    demo_.validation = contextOptions(demo_.device).validation;
    demo_.lines = lines_.value_or(defaultLineMode(demo_.scene.particles));
    if (demo_.vsync && demo_.present == PresentPath::Shm)
      throw UsageError("--vsync: needs --present swapchain (MIT-SHM has no vsync)");
    if (!headless_) {
      try {
        const DemoSummary s = runDemoWindow(demo_);
        std::printf(
            "demo: %u frames in %.2f s, average %.1f fps (%ux%u, %u particles, %s, %s; "
            "GPU per frame: simulate %.2f ms, draw %.2f ms)\n",
            s.frames, s.seconds, s.seconds > 0 ? s.frames / s.seconds : 0.0, s.size.width,
            s.size.height, demo_.scene.particles, s.device.c_str(), s.presentMode.c_str(),
            s.simulateMs, s.drawMs);
        return s.validationMessages ? 1 : 0;
      } catch (const NoDisplay& e) {
        std::printf("demo: %s; rendering headless instead\n", e.what());
      }
    }
    FramePlan plan;
    plan.frames = demo_.frames ? demo_.frames : 90;
    plan.size = demo_.size;
    plan.folder = outputFolder("--out", out_);
    plan.lines = demo_.lines;
    plan.warmup = demo_.warmup;
    Context context(contextOptions(demo_.device));
    const double seconds = renderFrames(context, demo_.scene, plan);
    std::printf(
        "demo: %u headless frames in %.2f s, average %.1f fps (%ux%u, %u particles); "
        "wrote %s/frame_*.png\n",
        plan.frames, seconds, seconds > 0 ? plan.frames / seconds : 0.0, plan.size.width,
        plan.size.height, demo_.scene.particles, plan.folder.c_str());
    return finish(context, 0);
  }

 private:
  Options options_;
  DemoOptions demo_;
  std::optional<LineMode> lines_;  // --renderer; unset: defaultLineMode
  bool headless_ = false;
  std::string out_ = "lava-demo-frames";
};

}  // namespace

std::unique_ptr<Command> makeDemo(CLI::App& app) {
  return std::make_unique<DemoCommand>(app);
}

}  // namespace lava::app
