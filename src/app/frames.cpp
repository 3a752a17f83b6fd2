#include "frames.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "host/output.h"
#include "lava/camera.h"
#include "lava/simulation.h"
#include "options.h"
#include "runtime.h"
#include "paths.h"

namespace lava::app {

VkExtent2D parseSize(const std::string& source, const std::string& text) {
  unsigned w = 0, h = 0;
  if (std::sscanf(text.c_str(), "%ux%u", &w, &h) != 2 || w == 0 || h == 0 || w > 65536 ||
      h > 65536 || text.find_first_not_of("0123456789x") != std::string::npos ||
      text != std::to_string(w) + "x" + std::to_string(h))
    throw UsageError(source + ": expected WIDTHxHEIGHT with each in [1, 16384], got '" +
                           text + "'");
  return {w, h};
}

void checkSize(const Device& device, VkExtent2D size) {
  const uint32_t limit = device.limits().maxImageDimension2D;
  if (size.width > limit || size.height > limit)
    throw UsageError("--size: expected each side in [1, " + std::to_string(limit) +
                           "] on this device, got " + std::to_string(size.width) + "x" +
                           std::to_string(size.height));
}

void createOutputFolder(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
    throw UsageError("--out: cannot create folder '" + path + "': " + std::strerror(errno));
}

LineMode parseLineMode(const std::string& source, const std::string& text) {
  if (text == "lines") return LineMode::Lines;
  if (text == "splat") return LineMode::Splat;
  throw UsageError(source + ": expected lines or splat, got '" + text + "'");
}

void addLookFlags(Options& options, LookOptions& look) {
  options.add("look",
              "lava (molten rock: cooling crust, tone-mapped energy, glow) or plain (the "
              "lab handout's added 1-pixel lines, for comparison) [lava]",
              [&look](const std::string& src, const std::string& t) {
                if (t == "lava")
                  look.style = LookStyle::Lava;
                else if (t == "plain")
                  look.style = LookStyle::Plain;
                else
                  throw UsageError(src + ": expected lava or plain, got '" + t + "'");
              });
  options.add("exposure", "lava look: brightness before the tone map, (0, 16] [1]",
              [&look](const std::string& src, const std::string& t) {
                look.settings.exposure = float(parseNumber(src, t, 0, 16, true));
              });
  options.add("bloom", "lava look: strength of the glow around bright lava, 0..4 (0: none) [1]",
              [&look](const std::string& src, const std::string& t) {
                look.settings.bloom = float(parseNumber(src, t, 0, 4));
              });
  options.add("bloom-threshold",
              "lava look: energy per pixel below which lava does not glow, 0..16 [0.1]",
              [&look](const std::string& src, const std::string& t) {
                look.settings.threshold = float(parseNumber(src, t, 0, 16));
              });
}

LineMode defaultLineMode(uint64_t particles) {
  return particles >= kSplatFrom ? LineMode::Splat : LineMode::Lines;
}

double renderFrames(Device& device, const Scene& scene, const FramePlan& plan) {
  checkSize(device, plan.size);
  createOutputFolder(plan.folder);
  Progress progress("render", plan.frames);
  const auto start = std::chrono::steady_clock::now();
  host::FrameRun run;
  run.frames = plan.frames;
  run.fps = plan.fps;
  run.size = plan.size;
  run.warmup = plan.warmup;
  run.start = plan.start;
  run.series = plan.series;
  run.seriesEvery = plan.seriesEvery;
  run.lines = plan.lines;
  run.style = plan.look.style;
  run.look = plan.look.settings;
  if (!plan.backend.gpu) run.cpu = {plan.backend.cpuThreads(), plan.backend.kernel};
  host::renderFrames(device, scene, run,
                     [&](uint32_t frame, const std::vector<uint8_t>& pixels) {
                       char name[32];
                       std::snprintf(name, sizeof(name), "/frame_%05u.png", frame);
                       host::writePng(plan.folder + name, plan.size.width, plan.size.height,
                                      pixels);
                       progress.update(frame + 1);
                     });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace lava::app
