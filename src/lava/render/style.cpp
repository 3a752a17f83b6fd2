#include "style.h"

namespace lava::detail {

glm::vec4 lineStyle(const Scene& scene) {
  return {scene.lineScale, 8.0f, 5.0f, 0.0f};
}

void setViewport(const DeviceContext& c, VkCommandBuffer commands, VkExtent2D extent) {
  const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, extent};
  c.vk.CmdSetViewport(commands, 0, 1, &viewport);
  c.vk.CmdSetScissor(commands, 0, 1, &scissor);
}

}  // namespace lava::detail
