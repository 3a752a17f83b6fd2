#include "demo_panel.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

namespace lava::window {

bool DemoPanel::build(const char* device, const std::function<DemoFigures()>& figures,
                      DemoControls& controls, host::FrameRenderer& renderer,
                      Simulation& simulation, Scene& running) {
  if (!controls.showPanel) return false;
  // The figures are refreshed four times a second: readable, and a panel that did not
  // change is not drawn again (Ui::record copies the one it drew).
  const double now = glfwGetTime();
  if (now - shownAt_ >= 0.25 || now < shownAt_) {
    shownAt_ = now;
    shown_ = figures();
  }
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::Begin("Lava", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s", device);
  ImGui::Text("%.1f fps   GPU: simulate %.2f ms, draw %.2f ms", shown_.fps, shown_.simulateMs,
              shown_.drawMs);
  ImGui::Text("alive %llu / %llu   t = %.2f s", static_cast<unsigned long long>(shown_.alive),
              static_cast<unsigned long long>(running.particles()), shown_.seconds);
  ImGui::Checkbox("pause [Space]", &controls.paused);
  ImGui::SameLine();
  if (ImGui::Button("step [N]")) controls.stepOnce = true;
  ImGui::SameLine();
  if (ImGui::Button("reset [R]")) controls.reset = true;
  ImGui::SameLine();
  if (ImGui::Button("screenshot [P]")) controls.screenshot = true;
  ImGui::SliderFloat("speed", &controls.speed, 0.0f, 4.0f);
  bool splat = renderer.lineMode() == LineMode::Splat;
  if (ImGui::Checkbox("compute line splatting (off: graphics pipeline)", &splat))
    renderer.setLineMode(splat ? LineMode::Splat : LineMode::Lines);
  bool lava = renderer.style() == LookStyle::Lava;
  if (ImGui::Checkbox("lava look (off: plain lines)", &lava))
    renderer.setStyle(lava ? LookStyle::Lava : LookStyle::Plain);
  if (lava) {
    LookSettings look = renderer.settings();
    bool changed = ImGui::SliderFloat("exposure", &look.exposure, 0.05f, 16.0f, "%.2f",
                                      ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    changed |=
        ImGui::SliderFloat("bloom", &look.bloom, 0.0f, 4.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
    if (changed) renderer.setSettings(look);
  }

  // Closed at start: the panel is drawn every frame, and on a CPU device a short panel
  // costs a fraction of a long one.
  const bool edited =
      ImGui::CollapsingHeader("scene") && editScene(controls, simulation, running);
  ImGui::TextDisabled("drag: orbit  right-drag: height  wheel: zoom  H: hide");
  ImGui::End();
  return edited;
}

// The scene section: a live edit to `simulation` and `running` (true when taken), the restart.
bool DemoPanel::editScene(DemoControls& controls, Simulation& simulation, Scene& running) {
  bool edited = false;
  switch (scene_.draw(running)) {
    case ScenePanel::Change::Live:
      try {
        simulation.setScene(scene_.edited());
        running = scene_.edited();
        scene_.setMessage("");
        edited = true;
      } catch (const Error& e) {
        scene_.setMessage(e.what());  // an invalid value: the running scene stays
      }
      break;
    case ScenePanel::Change::Structure:
      scene_.setMessage("emitters, their capacities or the flow's emitters changed: restart to "
                        "apply");
      break;
    case ScenePanel::Change::None:
      break;
  }
  if (ImGui::Button("restart with this scene")) controls.restart = true;
  return edited;
}

}  // namespace lava::window
