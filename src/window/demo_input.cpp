#include "demo_input.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lava::window {

DemoInput::DemoInput(GLFWwindow* window) : window_(window) {
  glfwSetWindowUserPointer(window, this);
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action == GLFW_PRESS)
      static_cast<DemoInput*>(glfwGetWindowUserPointer(w))->pressed_.push_back(key);
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) {
    static_cast<DemoInput*>(glfwGetWindowUserPointer(w))->resized_ = true;
  });
}

bool DemoInput::takeResized() {
  return std::exchange(resized_, false);
}

void DemoInput::apply(DemoControls& controls, OrbitCamera& camera) {
  const ImGuiIO& io = ImGui::GetIO();
  for (const int key : pressed_) {
    if (io.WantCaptureKeyboard) break;  // typed into the panel
    switch (key) {
      case GLFW_KEY_SPACE:
        controls.paused = !controls.paused;
        break;
      case GLFW_KEY_N:
        controls.stepOnce = true;
        break;
      case GLFW_KEY_R:
        controls.reset = true;
        break;
      case GLFW_KEY_P:
        controls.screenshot = true;
        break;
      case GLFW_KEY_H:
        controls.showPanel = !controls.showPanel;
        break;
      case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(window_, 1);
        break;
      default:
        break;
    }
  }
  pressed_.clear();
  if (io.WantCaptureMouse) return;
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
    camera.yaw -= io.MouseDelta.x * 0.006f;
    camera.pitch = std::clamp(camera.pitch + io.MouseDelta.y * 0.006f, -0.05f, 1.5f);
  }
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Right)) camera.target.y += io.MouseDelta.y * 0.01f;
  camera.distance = std::clamp(camera.distance * std::pow(0.9f, io.MouseWheel), 0.5f, 60.0f);
}

}  // namespace lava::window
