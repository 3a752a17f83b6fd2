// Dear ImGui over GLFW and Vulkan (Debian's libimgui-dev 1.86, whose Vulkan backend draws in a
// render pass). The panel is opaque and drawn into an image of its own only when it changed
// (ImGui's draw data differs from the last drawn); each frame copies its windows' rectangles over
// the scene. On a CPU device that is the difference between shading and blending every pixel of the
// panel each frame and a memcpy of its rows. A target that takes no
// copies gets the panel drawn over it, in a pass of its own.
#pragma once
#include <vulkan/vulkan.h>

#include <map>

#include "host/offscreen.h"
#include "host/vulkan.h"
#include "lava/device.h"

struct GLFWwindow;

namespace lava::window {

class Ui {
 public:
  Ui(Device& device, GLFWwindow* window, VkFormat colorFormat, uint32_t imageCount);
  ~Ui();
  Ui(const Ui&) = delete;
  Ui& operator=(const Ui&) = delete;

  // Records the panel ImGui::Render() produced into `target`'s colour image, which is in
  // COLOR_ATTACHMENT_OPTIMAL and is left so.
  void record(VkCommandBuffer commands, const host::FrameTarget& target);
  // Forgets the framebuffers of the old targets (after a resize).
  void forgetTargets() { framebuffers_.clear(); }

 private:
  void drawPanel(VkCommandBuffer commands, VkExtent2D extent);

  Device& lavaDevice_;
  VkDevice device_;
  VkFormat format_;
  host::OwnedDescriptorPool pool_;
  host::OwnedRenderPass overPass_;   // over the frame (a target that takes no copies)
  host::OwnedRenderPass panelPass_;  // into the panel's image, cleared
  std::map<VkImageView, host::OwnedFramebuffer> framebuffers_;
  host::Image panel_;
  host::OwnedFramebuffer panelFramebuffer_;
  VkExtent2D panelExtent_{0, 0};
  uint64_t drawnKey_ = 0;  // the draw data in panel_ (0: none)
};

}  // namespace lava::window
