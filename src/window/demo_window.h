// The interactive lava demo: a GLFW window presenting the program's frames through a
// swapchain or MIT-SHM, with a fixed-step simulation decoupled from the frame rate. Its
// frame loop is here; the keys and mouse are DemoInput's, the panel is DemoPanel's.
#pragma once
#include <vulkan/vulkan.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "host/frame_renderer.h"
#include "lava/renderer.h"
#include "lava/scene.h"
#include "presenter.h"

namespace lava::window {

// No window could be opened (no display, no Vulkan surface support): fall back to headless.
class NoDisplay : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DemoOptions {
  Scene scene;
  VkExtent2D size{1280, 720};
  uint32_t frames = 0;  // exit after this many presented frames; 0: until the window closes
  bool vsync = false;   // FIFO presentation; else mailbox or immediate when offered
  std::optional<PresentPath> present;  // unset: MIT-SHM for CPU devices on X11, else swapchain
  LineMode lines = LineMode::Lines;
  LookStyle style = LookStyle::Lava;
  LookSettings look;
  double warmup = 0.0;  // seconds simulated before the first frame, from `start`
  std::optional<State> start;  // the state the run starts from (none: the scene's initial)
  std::optional<unsigned> device;
  bool validation = false;
  // Stepped by the CPU backend, the device drawing each frame's state (lava demo --backend);
  // none: the device steps it.
  std::optional<host::FrameRun::CpuStepping> cpu;
};

struct DemoSummary {
  uint32_t frames = 0;
  double seconds = 0.0;
  double cpuSeconds = 0.0;  // of the process, all its threads, over the frames
  VkExtent2D size{0, 0};
  std::string device;
  std::string presentMode;
  uint32_t validationMessages = 0;
  double simulateMs = 0.0;  // GPU time per frame (smoothed timestamps) of the simulation, or
                            // the CPU's wall time when it steps the run (DemoOptions::cpu)
  double drawMs = 0.0;      // and of the draw
};

// Runs the window until closed or `frames` are presented; throws NoDisplay when there is
// no window to open.
DemoSummary runDemoWindow(const DemoOptions& options);

}  // namespace lava::window
