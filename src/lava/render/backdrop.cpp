// Backdrop: the ground plane and the scene's colliders (or, in a scene without colliders
// whose vent is a disc, a crater of scenery under it), generated from gl_VertexIndex, opaque
// and writing depth; in the lava look the sky (sky.vert) where they leave the far plane.
#include <glm/gtc/type_ptr.hpp>

#include "lava/renderer.h"
#include "shared.h"
#include "style.h"
#include "vulkan/commands.h"
#include "vulkan/pipeline.h"
#include "vulkan/shaders.h"

namespace lava {

struct Backdrop::Impl {
  const detail::DeviceContext& c;
  detail::UniquePipelineLayout layout;
  detail::UniquePipeline pipeline;
  detail::UniquePipeline sky;  // the lava look's: bands coloured per vertex, no depth write
  bool hasDepth = true;
};

Backdrop::Backdrop(Device& device, const RenderFormats& formats)
    : impl_(std::make_unique<Impl>(Impl{device.context(), {}, {}})) {
  Impl& m = *impl_;
  detail::checkTarget(m.c, formats);
  m.layout = detail::createPipelineLayout(m.c, VK_NULL_HANDLE,
                                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                          sizeof(gpu::BackdropParams));
  const detail::GraphicsPipelineDesc solids{LAVA_SPIRV(spirv::kGroundVertSpv),
                                            LAVA_SPIRV(spirv::kGroundFragSpv), formats};
  m.pipeline = detail::createGraphicsPipeline(m.c, m.layout, solids);
  detail::GraphicsPipelineDesc sky{LAVA_SPIRV(spirv::kSkyVertSpv),
                                   LAVA_SPIRV(spirv::kLinesFragSpv), formats};
  sky.depthWrite = false;
  m.sky = detail::createGraphicsPipeline(m.c, m.layout, sky);
  m.hasDepth = formats.depth != VK_FORMAT_UNDEFINED;
}

Backdrop::~Backdrop() = default;

void Backdrop::recordDraw(VkCommandBuffer commands, const View& view, const Scene& scene,
                          LookStyle style) const {
  const Impl& m = *impl_;
  gpu::BackdropParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  const Emitter& vent = scene.emitters.at(0);
  p.vent = {vent.position.x, vent.position.y, vent.position.z, vent.radius};
  const bool lava = style == LookStyle::Lava;
  p.eye = {view.eye.x, view.eye.y, view.eye.z, lava ? gpu::kLookLava : gpu::kLookPlain};
  detail::setViewport(m.c, commands, view.extent);
  const auto draw = [&](uint32_t kind, const Vec3& at, const glm::vec4& size, uint32_t vertices) {
    p.solid = {at.x, at.y, at.z, float(kind)};
    p.size = size;
    m.c.vk.CmdPushConstants(commands, m.layout,
                            VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                            sizeof(p), &p);
    m.c.vk.CmdDraw(commands, vertices, 1, 0, 0);
  };
  const auto drawSky = [&] {
    m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.sky);
    m.c.vk.CmdDraw(commands, gpu::kSkyVertices, 1, 0, 0);
  };
  if (lava && !m.hasDepth) drawSky();  // without a depth test, first, under the solids
  m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline);
  draw(gpu::kSolidGround, {}, {}, gpu::kGroundVertices);
  for (const Collider& c : scene.colliders) {
    switch (c.type) {
      case ColliderType::Cone:
        draw(gpu::kSolidCone, c.position, {c.baseRadius, c.topRadius, c.height, 0.0f},
             gpu::kConeVertices);
        break;
      case ColliderType::Sphere:
        draw(gpu::kSolidSphere, c.position, {c.radius, 0.0f, 0.0f, 0.0f}, gpu::kSphereVertices);
        break;
      case ColliderType::Box:
        draw(gpu::kSolidBox, c.position, {c.size.x, c.size.y, c.size.z, 0.0f}, gpu::kBoxVertices);
        break;
      case ColliderType::Plane: {
        const glm::vec3 n = glm::normalize(glm::vec3(c.normal.x, c.normal.y, c.normal.z));
        draw(gpu::kSolidPlane, c.position, {n, 0.0f}, gpu::kPlaneVertices);
        break;
      }
    }
  }
  if (scene.colliders.empty() && vent.shape == Shape::Disc) {
    // Scenery only: the crater of a scene without colliders (the seed scene's) is not solid.
    const float top = std::max(vent.position.y, 0.05f);
    const float rim = std::max(vent.radius, 0.05f) * 1.3f;
    draw(gpu::kSolidCone, {vent.position.x, 0.0f, vent.position.z},
         {rim + top * 0.9f, rim, top, 0.0f}, gpu::kConeVertices);
  }
  if (lava && m.hasDepth) drawSky();  // last, at the far plane: where no solid is
}

}  // namespace lava
