// The demo's input: what the user asked for (DemoControls, set by the keys and by the
// panel's buttons alike), and the window's keys, mouse and size changes (DemoInput).
#pragma once
#include <vector>

#include "lava/camera.h"

struct GLFWwindow;

namespace lava::window {

// The user's requests, read by the frame loop; one-shot requests are cleared when served.
struct DemoControls {
  bool paused = false;
  bool stepOnce = false;    // one step while paused
  bool reset = false;       // the running scene back to its initial state
  bool restart = false;     // a new simulation of the panel's edited scene
  bool screenshot = false;  // the next frame saved as a PNG, offscreen
  bool showPanel = true;
  float speed = 1.0f;  // simulated seconds per second
};

// Owns the window's key and framebuffer-size callbacks (install it before Dear ImGui, which
// chains to them). Key presses are queued as they arrive: ImGui 1.86 keeps only whether a
// key is down when a frame starts, so a tap pressed and released within one slow frame
// would be lost.
class DemoInput {
 public:
  explicit DemoInput(GLFWwindow* window);
  DemoInput(const DemoInput&) = delete;
  DemoInput& operator=(const DemoInput&) = delete;

  // Applies the keys pressed since the last frame and this frame's mouse: Space pause, N
  // step, R reset, P screenshot, H panel, Esc quit; drag orbit, right-drag height, wheel
  // zoom. Call between ImGui::NewFrame and ImGui::Render; keys typed into the panel and
  // the mouse over it are the panel's.
  void apply(DemoControls& controls, OrbitCamera& camera);
  // Whether the framebuffer changed size since the last call.
  bool takeResized();

 private:
  GLFWwindow* window_;
  std::vector<int> pressed_;  // GLFW keys, in order
  bool resized_ = false;
};

}  // namespace lava::window
