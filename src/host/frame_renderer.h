// One frame of the `lava` program as a paragraph: the backdrop (drawn once per view into
// images of its own; while the view repeats, its colour is copied into each frame, a memcpy
// on a CPU device instead of shading every pixel, made by the host itself where the frame
// lives in host memory, and its depth is tested against in place), the simulation's draw
// preparation (the splat, tested against the frame's depth, and the lava look's glow), the
// lines, an overlay (the demo's panel), then the target's final layout. Both looks take
// this path.
#pragma once
#include <functional>
#include <optional>
#include <vector>

#include "lava/camera.h"
#include "lava/renderer.h"
#include "lava/simulation.h"
#include "offscreen.h"

namespace lava::host {

class FrameRenderer {
 public:
  FrameRenderer(Device& device, VkFormat colorFormat, LookStyle style = LookStyle::Lava);

  void setLineMode(LineMode mode) { lines_.setMode(mode); }
  LineMode lineMode() const { return lines_.mode(); }
  void setStyle(LookStyle style) { lines_.setStyle(style); }
  LookStyle style() const { return lines_.style(); }
  // Throws InvalidArgument naming a setting out of its range.
  void setSettings(const LookSettings& settings) { lines_.setSettings(settings); }
  const LookSettings& settings() const { return lines_.settings(); }

  // Records the frame into `target` in frame slot `frame` (below the device's; that
  // slot's previous frame must have finished). The color and depth images' previous
  // contents are discarded; the depth image is left alone while the cached backdrop's depth
  // serves, and a target with hostColor may have its colour written by the host here, before
  // the commands are submitted. `overlay` records with the color image in
  // COLOR_ATTACHMENT_OPTIMAL and must leave it there; it may begin a render pass of its own.
  // A new target size waits for the device to be idle first (the renderer's per-size
  // resources are rebuilt).
  void record(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
              const FrameTarget& target, const OrbitCamera& camera,
              const std::function<void(VkCommandBuffer)>& overlay = {});
  // Whether the last record() copied the cached backdrop instead of drawing it, and whether
  // the host wrote that copy (for tests).
  bool backdropReused() const { return backdropReused_; }
  bool backdropWrittenByHost() const { return backdropByHost_; }

 private:
  struct BackdropCache {
    Image color, depth;
    std::vector<float> key;  // what it was drawn from (view, look, solids)
    bool drawn = false;
    // The colour read back for targets the host writes (FrameTarget::hostColor): recorded
    // in frame slot `pixelsFrame`, ready once that slot is recorded again.
    ReadbackBuffer pixels;
    enum class Pixels { None, Recorded, Ready } pixelsState = Pixels::None;
    uint32_t pixelsFrame = 0;
  };
  void resize(VkExtent2D extent);
  bool copyBackdrop(VkCommandBuffer commands, uint32_t frame, const FrameTarget& target,
                    const View& view, const Scene& scene);
  bool writeBackdropFromHost(VkCommandBuffer commands, uint32_t frame, const FrameTarget& target);
  void beginRendering(VkCommandBuffer commands, VkImageView color, VkImageView depth,
                      VkExtent2D extent, bool load) const;

  Device& device_;
  VkFormat colorFormat_;
  Backdrop backdrop_;
  LineRenderer lines_;
  BackdropCache cache_;
  VkExtent2D extent_{0, 0};
  bool backdropReused_ = false;
  bool backdropByHost_ = false;
  PFN_vkCmdBeginRendering cmdBeginRendering_;
  PFN_vkCmdEndRendering cmdEndRendering_;
};

// The image of the scene drawn offscreen: its pixels once the frame finished.
std::vector<uint8_t> renderOffscreen(const Device& device, FrameRenderer& renderer,
                                     const GpuSimulation& simulation, const OffscreenTarget& target,
                                     const OrbitCamera& camera);

// A run of offscreen frames, as `lava render` and Python's lava.render make them: the scene
// simulated `warmup` seconds, then a frame every 1/fps simulated seconds as the camera
// orbits slowly.
struct FrameRun {
  uint32_t frames = 1;
  double fps = 30.0;
  VkExtent2D size{1280, 720};
  double warmup = 3.0;  // s, from `start`
  std::optional<State> start;  // the state the run starts from (none: the scene's initial)
  LineMode lines = LineMode::Lines;
  LookStyle style = LookStyle::Lava;
  LookSettings look;
  // Also the state every seriesEvery steps as a VTK time series in `series` (docs/cli.md,
  // "Series"), continued when the run starts from `start`; none when empty.
  std::string series;
  uint64_t seriesEvery = 0;
  // Stepped by the CPU backend (docs/cli.md, `lava render`) and drawn by the device, which is
  // given the state before each frame: the same bytes as the GPU's steps, and the implicit
  // flow, which runs on the CPU backends only. None: the device steps it.
  struct CpuStepping {
    unsigned threads = 1;
    CpuKernel kernel = CpuKernel::Reference;
  };
  std::optional<CpuStepping> cpu;
};
// What the device draws of a run the CPU steps: the scene with the flow's explicit solver
// (the only one the GPU flow builds; it never steps there), and each state without the
// implicit flow's pressures, which drawing does not read.
Scene drawnScene(Scene scene);
State drawnState(const State& state);

// `sink` receives each frame's RGBA8 pixels (rows of size.width, top first) in order; an
// exception from it ends the run.
void renderFrames(Device& device, const Scene& scene, const FrameRun& run,
                  const std::function<void(uint32_t frame, const std::vector<uint8_t>& rgba)>& sink);

}  // namespace lava::host
