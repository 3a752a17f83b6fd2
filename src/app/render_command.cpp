// `lava render`: PNG frames of the lava crater with no display, from the same renderer the
// window uses, drawn into an offscreen image; `--video` also encodes them with ffmpeg.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "common/files.h"
#include "commands.h"
#include "frames.h"
#include "host/output.h"
#include "lava/device.h"
#include "options.h"
#include "paths.h"
#include "resume.h"
#include "runtime.h"

namespace lava::app {
namespace {

extern "C" char** environ;

// ffmpeg on the PATH, found without a shell.
std::string findFfmpeg() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string candidate =
        (end > start ? dirs.substr(start, end - start) : std::string(".")) + "/ffmpeg";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

// Runs ffmpeg with `args` (no shell: any character in a path is just a character); its
// exit status, or -1 when it could not start.
int runFfmpeg(const std::string& ffmpeg, const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(ffmpeg.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class RenderCommand final : public Command {
 public:
  explicit RenderCommand(CLI::App& app)
      : Command(app, "render", "write PNG frames of the scene (no display needed)"),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    options_.addInteger("frames", "frames to write, 1..100000 (required)", plan_.frames, 1, 100000,
                        true);
    options_.add("fps", "frames per simulated second, (0, 1000] [30]",
                 [this](const std::string& src, const std::string& t) {
                   plan_.fps = parseNumber(src, t, 0, 1000, true);
                 });
    options_.add(
        "size", "image size WxH, each 1..the device limit [1280x720]",
        [this](const std::string& src, const std::string& t) { plan_.size = parseSize(src, t); });
    options_.add("resume",
                 "start from the state a checkpoint FILE.npz holds (lava simulate "
                 "--checkpoint), in its scene; --warmup seconds more before the first frame",
                 [](const std::string&, const std::string&) {});  // read before resolve()
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
    addBackendFlags(options_, plan_.backend);
    addLookFlags(options_, plan_.look);
    addSeriesFlags(options_, plan_.series, plan_.seriesEvery);
    options_.add(
        "video", "also encode FILE.mp4 with ffmpeg (must be installed)",
        [this](const std::string& src, const std::string& t) {
          checkOutputPath(src, t, ".mp4");
          ffmpeg_ = findFfmpeg();
          if (ffmpeg_.empty())
            throw UsageError(src + ": needs ffmpeg on the PATH (Debian: apt install ffmpeg)");
          video_ = t;
        });
  }

  int run() override {
    std::optional<Snapshot> resumed = readResume(options_, scene_);
    options_.resolve();
    checkSeriesFlags(plan_.series, plan_.seriesEvery);
    if (resumed) {
      checkResumedScene(scene_, resumed->scene);
      plan_.start = std::move(resumed->state);
    }
    Device device(deviceOptions(device_));
    renderFrames(device, scene_, plan_);
    std::printf("render: wrote %u frames (%ux%u) to %s/frame_*.png\n", plan_.frames,
                plan_.size.width, plan_.size.height, plan_.folder.c_str());
    if (!video_.empty()) {
      // Exactly this run's frames (an older run's may follow them in the folder), odd sizes
      // padded to even (H.264 in yuv420p needs them), into a temporary renamed into place.
      const size_t slash = video_.find_last_of('/');
      const std::string temp = (slash == std::string::npos ? "" : video_.substr(0, slash + 1)) +
                               ".lava-video-" + std::to_string(getpid()) + ".mp4";
      char rate[32];
      std::snprintf(rate, sizeof(rate), "%g", plan_.fps);
      // clang-format off
      const int status = runFfmpeg(
          ffmpeg_, {"-loglevel", "error", "-y", "-framerate", rate, "-start_number", "0", "-i",
                    plan_.folder + "/frame_%05d.png", "-frames:v", std::to_string(plan_.frames),
                    "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                    "yuv420p", "-f", "mp4", temp});
      // clang-format on
      if (status != 0 || !common::moveIntoPlace(temp, video_)) {
        std::remove(temp.c_str());
        std::fprintf(stderr, "lava: ffmpeg failed to encode '%s'%s\n", video_.c_str(),
                     status < 0 ? " (it did not start)" : "");
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
  std::string video_, ffmpeg_;
};

}  // namespace

std::unique_ptr<Command> makeRender(CLI::App& app) {
  return std::make_unique<RenderCommand>(app);
}

}  // namespace lava::app
