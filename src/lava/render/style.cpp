#include "style.h"

#include <algorithm>

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

void recordSolids(const DeviceContext& c, VkCommandBuffer commands, VkPipelineLayout layout,
                  const Scene& scene, gpu::BackdropParams& p) {
  const auto draw = [&](uint32_t kind, const Vec3& at, const glm::vec4& size, uint32_t vertices) {
    p.solid = {at.x, at.y, at.z, float(kind)};
    p.size = size;
    c.vk.CmdPushConstants(commands, layout,
                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(p),
                          &p);
    c.vk.CmdDraw(commands, vertices, 1, 0, 0);
  };
  draw(gpu::kSolidGround, {}, {}, gpu::kGroundVertices);
  for (const Collider& k : scene.colliders) {
    switch (k.type) {
      case ColliderType::Cone:
        draw(gpu::kSolidCone, k.position, {k.baseRadius, k.topRadius, k.height, 0.0f},
             gpu::kConeVertices);
        break;
      case ColliderType::Sphere:
        draw(gpu::kSolidSphere, k.position, {k.radius, 0.0f, 0.0f, 0.0f}, gpu::kSphereVertices);
        break;
      case ColliderType::Box:
        draw(gpu::kSolidBox, k.position, {k.size.x, k.size.y, k.size.z, 0.0f}, gpu::kBoxVertices);
        break;
      case ColliderType::Plane: {
        const glm::vec3 n = glm::normalize(glm::vec3(k.normal.x, k.normal.y, k.normal.z));
        draw(gpu::kSolidPlane, k.position, {n, 0.0f}, gpu::kPlaneVertices);
        break;
      }
    }
  }
  const Emitter& vent = scene.emitters.at(0);
  if (scene.colliders.empty() && vent.shape == Shape::Disc) {
    // Scenery only: the crater of a scene without colliders (crater.toml's) is not solid.
    const float top = std::max(vent.position.y, 0.05f);
    const float rim = std::max(vent.radius, 0.05f) * 1.3f;
    draw(gpu::kSolidCone, {vent.position.x, 0.0f, vent.position.z},
         {rim + top * 0.9f, rim, top, 0.0f}, gpu::kConeVertices);
  }
}

}  // namespace lava::detail
