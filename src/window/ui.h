// Dear ImGui over GLFW and Vulkan (Debian's libimgui-dev with its backends), drawing
// inside the LineRenderer's render pass; the demo builds its panel between frames.
#pragma once
#include <vulkan/vulkan.h>

#include "context.h"

struct GLFWwindow;

namespace lava {

class Ui {
 public:
  Ui(Context& context, GLFWwindow* window, VkRenderPass renderPass, uint32_t imageCount);
  ~Ui();
  Ui(const Ui&) = delete;
  Ui& operator=(const Ui&) = delete;

 private:
  VkDevice device_;
  UniqueDescriptorPool pool_;
};

}  // namespace lava
