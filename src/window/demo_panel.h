// The demo's panel (Dear ImGui): the device and the running figures, the controls, the
// look, and the scene editor with live changes and restarts.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "demo_input.h"
#include "host/frame_renderer.h"
#include "lava/scene.h"
#include "lava/simulation.h"
#include "scene_panel.h"

namespace lava::window {

// The running figures the panel shows.
struct DemoFigures {
  double fps = 0.0;
  double simulateMs = 0.0, drawMs = 0.0;  // GPU time per frame
  double seconds = 0.0;                   // simulated
  uint64_t alive = 0;                     // slots born at least once
};

class DemoPanel {
 public:
  explicit DemoPanel(const Scene& scene) : scene_(scene) {}

  // Builds this frame's panel (between ImGui::NewFrame and ImGui::Render), unless
  // controls.showPanel is off. The buttons set `controls`; the look goes to `renderer`; a
  // live scene edit goes to `simulation` and, when it takes it, to `running` (then true).
  // `figures` is asked only when the shown figures are refreshed (four times a second).
  bool build(const char* device, const std::function<DemoFigures()>& figures,
             DemoControls& controls, host::FrameRenderer& renderer, Simulation& simulation,
             Scene& running);

  // The scene a restart would run.
  const Scene& edited() const { return scene_.edited(); }
  // The outcome of a restart or edit (an invalid value, "restarted"), shown.
  void setMessage(std::string message) { scene_.setMessage(std::move(message)); }

 private:
  bool editScene(DemoControls& controls, Simulation& simulation, Scene& running);

  ScenePanel scene_;
  double shownAt_ = -1.0;  // glfwGetTime() when `shown_` was refreshed
  DemoFigures shown_;
};

}  // namespace lava::window
