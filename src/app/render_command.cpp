// `lava render`: PNG frames of the lava crater with no display, from the same renderer the
// window uses, drawn into an offscreen image.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

#include "commands.h"
#include "image_io.h"
#include "line_renderer.h"
#include "offscreen_target.h"
#include "options.h"
#include "runtime.h"
#include "vk_check.h"

namespace lava::app {
namespace {

class RenderCommand final : public Command {
 public:
  explicit RenderCommand(CLI::App& app)
      : Command(app.add_subcommand("render", "write PNG frames of the scene (no display needed)")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add("frames", Kind::Number, "frames to write, 1..100000 (required)",
                 [this](const std::string& src, const std::string& t) {
                   frames_ = static_cast<uint32_t>(parseInteger(src, t, 1, 100000));
                 }, true);
    options_.add("fps", Kind::Number, "frames per simulated second, (0, 1000] [30]",
                 [this](const std::string& src, const std::string& t) {
                   fps_ = parseNumber(src, t, 0, 1000, true);
                 });
    options_.add("size", Kind::Text, "image size WxH, each 1..the device limit [1280x720]",
                 [this](const std::string& src, const std::string& t) { size_ = parseSize(src, t); });
    options_.add("warmup", Kind::Number, "seconds simulated before the first frame, 0..600 [3]",
                 [this](const std::string& src, const std::string& t) {
                   warmup_ = parseNumber(src, t, 0, 600);
                 });
    options_.add("out", Kind::Text, "folder for frame_00000.png ... (created if missing)",
                 [this](const std::string& src, const std::string& t) { out_ = outputFolder(src, t); },
                 true);
  }

  int run() override {
    options_.resolve();
    Context context(contextOptions(device_));
    checkSize(context, size_);
    GpuSimulator simulator(context, scene_);
    LineRenderer renderer(context, simulator, OffscreenTarget::kColorFormat,
                          VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    OffscreenTarget target(context, renderer.renderPass(), size_);
    OrbitCamera camera;
    simulator.advance(static_cast<uint64_t>(std::llround(warmup_ / double(scene_.dt))));
    const double stepsPerFrame = 1.0 / (fps_ * double(scene_.dt));
    double owed = 0.0;
    Progress progress("render", frames_);
    for (uint32_t frame = 0; frame < frames_; ++frame) {
      if (frame > 0) {
        owed += stepsPerFrame;
        const double whole = std::floor(owed);
        owed -= whole;
        simulator.advance(static_cast<uint64_t>(whole));
      }
      camera.yaw = 0.6f + 0.15f * float(frame / fps_);
      const std::vector<uint8_t> pixels = renderOffscreen(context, renderer, target, camera, scene_);
      char name[32];
      std::snprintf(name, sizeof(name), "/frame_%05u.png", frame);
      writePng(out_ + name, size_.width, size_.height, pixels);
      progress.update(frame + 1);
    }
    std::printf("render: wrote %u frames (%ux%u) to %s/frame_*.png\n", frames_, size_.width,
                size_.height, out_.c_str());
    return finish(context, 0);
  }

 private:
  static VkExtent2D parseSize(const std::string& source, const std::string& text) {
    unsigned w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 ||
        text.find_first_not_of("0123456789x") != std::string::npos || w > 65536 || h > 65536)
      throw UsageError(source + ": expected WIDTHxHEIGHT with each in [1, 16384], got '" + text + "'");
    return {w, h};
  }

  static void checkSize(const Context& context, VkExtent2D size) {
    const uint32_t limit = context.limits().maxImageDimension2D;
    if (size.width > limit || size.height > limit)
      throw UsageError("--size: expected each side in [1, " + std::to_string(limit) +
                       "] on this device, got " + std::to_string(size.width) + "x" +
                       std::to_string(size.height));
  }

  static std::string outputFolder(const std::string& source, const std::string& path) {
    if (path.empty()) throw UsageError(source + ": expected a folder, got ''");
    if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
      throw UsageError(source + ": cannot create folder '" + path + "': " + std::strerror(errno));
    struct stat info {};
    if (stat(path.c_str(), &info) != 0 || !S_ISDIR(info.st_mode) || access(path.c_str(), W_OK) != 0)
      throw UsageError(source + ": '" + path + "' is not a writable folder");
    return path;
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  uint32_t frames_ = 0;
  double fps_ = 30.0;
  VkExtent2D size_{1280, 720};
  double warmup_ = 3.0;
  std::string out_;
};

}  // namespace

std::unique_ptr<Command> makeRender(CLI::App& app) { return std::make_unique<RenderCommand>(app); }

}  // namespace lava::app
