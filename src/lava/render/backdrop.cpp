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
  detail::GraphicsPipelineDesc sky{LAVA_SPIRV(spirv::kSkyVertSpv), LAVA_SPIRV(spirv::kColorFragSpv),
                                   formats};
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
  const auto drawSky = [&] {
    m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.sky);
    m.c.vk.CmdDraw(commands, gpu::kSkyVertices, 1, 0, 0);
  };
  if (lava && !m.hasDepth) drawSky();  // without a depth test, first, under the solids
  m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline);
  detail::recordSolids(m.c, commands, m.layout, scene, p);
  if (lava && m.hasDepth) drawSky();  // last, at the far plane: where no solid is
}

}  // namespace lava
