#include "style.h"

#include "shared.h"

namespace lava::detail {

glm::vec4 lineStyle(const Scene& scene, LookStyle style) {
  return {scene.lineScale, 8.0f, 5.0f, style == LookStyle::Lava ? gpu::kLookLava : gpu::kLookPlain};
}

void setViewport(const DeviceContext& c, VkCommandBuffer commands, VkExtent2D extent) {
  const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, extent};
  c.vk.CmdSetViewport(commands, 0, 1, &viewport);
  c.vk.CmdSetScissor(commands, 0, 1, &scissor);
}

}  // namespace lava::detail
