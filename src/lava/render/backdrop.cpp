// Backdrop: the ground plane and the crater cone, generated from gl_VertexIndex (no vertex
// buffer), opaque and depth-writing.
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
};

Backdrop::Backdrop(Device& device, const RenderFormats& formats)
    : impl_(std::make_unique<Impl>(Impl{device.context(), {}, {}})) {
  Impl& m = *impl_;
  m.layout = detail::createPipelineLayout(m.c, VK_NULL_HANDLE,
                                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                          sizeof(gpu::DrawParams));
  const detail::GraphicsPipelineDesc ground{LAVA_SPIRV(spirv::kGroundVertSpv),
                                            LAVA_SPIRV(spirv::kGroundFragSpv), formats.color,
                                            formats.depth};
  m.pipeline = detail::createGraphicsPipeline(m.c, m.layout, ground);
}

Backdrop::~Backdrop() = default;

void Backdrop::recordDraw(VkCommandBuffer commands, const View& view, const Scene& scene) const {
  const Impl& m = *impl_;
  gpu::DrawParams params{};
  params.viewProj = glm::make_mat4(view.viewProj.m);
  params.style = detail::lineStyle(scene);
  const Emitter& e = scene.emitters.at(0);
  params.crater = glm::vec4(e.position.x, e.position.y, e.position.z, e.radius);
  detail::setViewport(m.c, commands, view.extent);
  m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline);
  m.c.vk.CmdPushConstants(commands, m.layout,
                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                          sizeof(params), &params);
  m.c.vk.CmdDraw(commands, gpu::kGroundVertices, 1, 0, 0);
}

}  // namespace lava
