// Dear ImGui over GLFW and Vulkan (Debian's libimgui-dev 1.86, whose Vulkan backend draws
// in a render pass): the panel is recorded after the scene, in a one-subpass pass of its
// own that keeps the frame's color image in COLOR_ATTACHMENT_OPTIMAL.
#pragma once
#include <vulkan/vulkan.h>

#include <map>

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

  // Records the panel ImGui::Render() produced over `color` (a view of the frame's image).
  void record(VkCommandBuffer commands, VkImageView color, VkExtent2D extent);
  // Forgets the framebuffers of the old targets (after a resize).
  void forgetTargets() { framebuffers_.clear(); }

 private:
  VkDevice device_;
  host::OwnedDescriptorPool pool_;
  host::OwnedRenderPass renderPass_;
  std::map<VkImageView, host::OwnedFramebuffer> framebuffers_;
};

}  // namespace lava::window
