// Headless frames: the scene simulated and drawn offscreen, one PNG per frame. Used by
// `lava render` and by `lava demo` when there is no display.
#pragma once
#include <vulkan/vulkan.h>

#include <optional>
#include <string>

#include "lava/device.h"
#include "lava/renderer.h"
#include "lava/scene.h"
#include "lava/state.h"
#include "options.h"
#include "paths.h"

namespace lava::app {

class Options;

// How frames look: --look, --exposure, --bloom.
struct LookOptions {
  LookStyle style = LookStyle::Lava;
  LookSettings settings;
};
void addLookFlags(Options& options, LookOptions& look);

struct FramePlan {
  uint32_t frames = 1;
  double fps = 30.0;  // frames per simulated second
  VkExtent2D size{1280, 720};
  double warmup = 3.0;  // seconds simulated before the first frame
  std::optional<State> start;  // --resume's state (none: the scene's initial)
  std::string folder;   // frame_00000.png ... go here
  std::string series;   // --series DIR, with seriesEvery (none: empty)
  uint64_t seriesEvery = 0;
  LineMode lines = LineMode::Lines;
  LookOptions look;
  BackendChoice backend;  // which steps the run; the device draws it
};

VkExtent2D parseSize(const std::string& source, const std::string& text);
// Throws UsageError naming --size unless both sides fit the device's image limit.
void checkSize(const Device& device, VkExtent2D size);
// "lines" or "splat" for the flag named by `source`.
LineMode parseLineMode(const std::string& source, const std::string& text);
// Lines below kSplatFrom particles, the splat from there.
LineMode defaultLineMode(uint64_t particles);

// Returns the wall-clock seconds the frames took (simulation, drawing and PNG writing).
double renderFrames(Device& device, const Scene& scene, const FramePlan& plan);

}  // namespace lava::app
