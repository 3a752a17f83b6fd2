// `lava render`: PNG frames of the lava crater with no display, from the same renderer the
// window uses, drawn into an offscreen image; `--video` also encodes them with ffmpeg.
#include <cstdio>
#include <cstdlib>
#include <optional>

#include "commands.h"
#include "frames.h"
#include "host/output.h"
#include "lava/device.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

bool haveFfmpeg() {
  return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

class RenderCommand final : public Command {
 public:
  explicit RenderCommand(CLI::App& app)
      : Command(app.add_subcommand("render", "write PNG frames of the scene (no display needed)")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.add(
        "frames", "frames to write, 1..100000 (required)",
        [this](const std::string& src, const std::string& t) {
          plan_.frames = static_cast<uint32_t>(parseInteger(src, t, 1, 100000));
        },
        true);
    options_.add("fps", "frames per simulated second, (0, 1000] [30]",
                 [this](const std::string& src, const std::string& t) {
                   plan_.fps = parseNumber(src, t, 0, 1000, true);
                 });
    options_.add(
        "size", "image size WxH, each 1..the device limit [1280x720]",
        [this](const std::string& src, const std::string& t) { plan_.size = parseSize(src, t); });
    options_.add("warmup", "seconds simulated before the first frame, 0..600 [3]",
                 [this](const std::string& src, const std::string& t) {
                   plan_.warmup = parseNumber(src, t, 0, 600);
                 });
    options_.add(
        "out", "folder for frame_00000.png ... (created if missing)",
        [this](const std::string& src, const std::string& t) {
          plan_.folder = outputFolder(src, t);
        },
        true);
    options_.add("renderer",
                 "lines (the graphics pipeline, the reference) or splat (compute) [lines]",
                 [this](const std::string& src, const std::string& t) {
                   plan_.lines = parseLineMode(src, t);
                 });
    addLookFlags(options_, plan_.look);
    options_.add(
        "video", "also encode FILE.mp4 with ffmpeg (must be installed)",
        [this](const std::string& src, const std::string& t) {
          host::checkOutputPath(src, t, ".mp4");
          if (!haveFfmpeg())
            throw host::UsageError(src + ": needs ffmpeg on the PATH (Debian: apt install ffmpeg)");
          video_ = t;
        });
  }

  int run() override {
    options_.resolve();
    Device device(deviceOptions(device_));
    renderFrames(device, scene_, plan_);
    std::printf("render: wrote %u frames (%ux%u) to %s/frame_*.png\n", plan_.frames,
                plan_.size.width, plan_.size.height, plan_.folder.c_str());
    if (!video_.empty()) {
      char command[1024];
      std::snprintf(command, sizeof(command),
                    "ffmpeg -loglevel error -y -framerate %g -i '%s/frame_%%05d.png' "
                    "-c:v libx264 -pix_fmt yuv420p '%s' </dev/null",
                    plan_.fps, plan_.folder.c_str(), video_.c_str());
      if (std::system(command) != 0) {
        std::fprintf(stderr, "lava: ffmpeg failed to encode '%s'\n", video_.c_str());
        return finish(device, 1);
      }
      std::printf("render: encoded %s\n", video_.c_str());
    }
    return finish(device, 0);
  }

 private:
  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  FramePlan plan_;
  std::string video_;
};

}  // namespace

std::unique_ptr<Command> makeRender(CLI::App& app) {
  return std::make_unique<RenderCommand>(app);
}

}  // namespace lava::app
