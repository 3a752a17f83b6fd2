// LineRenderer: each alive particle's line, by the graphics pipeline (lines.vert pulls both
// ends from the particle buffer) or by the splat (splat.comp adds every line into a
// fixed-point buffer the size of the target; resolve.frag blends it over the scene).
#include "lava/renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include "lava/error.h"
#include "lava/simulation.h"
#include "shared.h"
#include "style.h"
#include "vulkan/buffer.h"
#include "vulkan/commands.h"
#include "vulkan/pipeline.h"
#include "vulkan/shaders.h"

namespace lava {

using detail::Buffer;

struct LineRenderer::Impl {
  detail::DeviceContext& c;
  RenderFormats formats;
  uint32_t framesInFlight;
  LineMode mode = LineMode::Lines;
  detail::UniqueDescriptorSetLayout lineSet, splatSet, resolveSet;
  detail::UniquePipelineLayout lineLayout, splatLayout, resolveLayout;
  detail::UniquePipeline linePipeline, splatPipeline, resolvePipeline;
  VkExtent2D extent{0, 0};
  std::vector<Buffer> accumulation;  // per frame slot: the splat's sums, one uint per pixel

  Impl(detail::DeviceContext& context, const RenderFormats& f, uint32_t frames)
      : c(context), formats(f), framesInFlight(frames) {}
};

LineRenderer::LineRenderer(Device& device, const RenderFormats& formats, uint32_t framesInFlight)
    : impl_(std::make_unique<Impl>(device.context(), formats, framesInFlight)) {
  if (framesInFlight < 1 || framesInFlight > 16)
    throw InvalidArgument("framesInFlight",
                          "expected 1 to 16, got " + std::to_string(framesInFlight));
  Impl& m = *impl_;
  const detail::DeviceContext& c = m.c;
  const VkShaderStageFlags drawStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  m.lineSet =
      detail::createPushLayout(c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, VK_SHADER_STAGE_VERTEX_BIT);
  m.lineLayout = detail::createPipelineLayout(c, m.lineSet, drawStages, sizeof(gpu::DrawParams));
  detail::GraphicsPipelineDesc lines{LAVA_SPIRV(spirv::kLinesVertSpv),
                                     LAVA_SPIRV(spirv::kLinesFragSpv), formats.color,
                                     formats.depth};
  lines.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  lines.additive = true;
  lines.depthWrite = false;  // glowing lines do not occlude
  m.linePipeline = detail::createGraphicsPipeline(c, m.lineLayout, lines);

  m.splatSet = detail::createPushLayout(
      c, {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  m.splatLayout = detail::createPipelineLayout(c, m.splatSet, VK_SHADER_STAGE_COMPUTE_BIT,
                                               sizeof(gpu::SplatParams));
  m.splatPipeline = detail::createComputePipeline(
      c, m.splatLayout, LAVA_SPIRV(spirv::kSplatCompSpv), {gpu::kWorkgroupSize});
  m.resolveSet = detail::createPushLayout(c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                          VK_SHADER_STAGE_FRAGMENT_BIT);
  m.resolveLayout = detail::createPipelineLayout(c, m.resolveSet, VK_SHADER_STAGE_FRAGMENT_BIT,
                                                 sizeof(gpu::SplatParams));
  detail::GraphicsPipelineDesc resolve{LAVA_SPIRV(spirv::kResolveVertSpv),
                                       LAVA_SPIRV(spirv::kResolveFragSpv), formats.color,
                                       formats.depth};
  resolve.additive = true;
  resolve.depthTest = false;
  resolve.depthWrite = false;
  m.resolvePipeline = detail::createGraphicsPipeline(c, m.resolveLayout, resolve);
}

LineRenderer::~LineRenderer() = default;

void LineRenderer::setMode(LineMode mode) {
  impl_->mode = mode;
}

LineMode LineRenderer::mode() const {
  return impl_->mode;
}

void LineRenderer::setExtent(VkExtent2D extent) {
  Impl& m = *impl_;
  if (extent.width == m.extent.width && extent.height == m.extent.height) return;
  if (extent.width == 0 || extent.height == 0)
    throw InvalidArgument("extent", "expected a non-empty size");
  m.accumulation.clear();
  for (uint32_t f = 0; f < m.framesInFlight; ++f)
    m.accumulation.emplace_back(
        m.c, VkDeviceSize{extent.width} * extent.height * sizeof(uint32_t),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
        detail::MemoryUse::Device);
  m.extent = extent;
}

namespace {

gpu::SplatParams splatParams(const GpuSimulation& simulation, const View& view) {
  gpu::SplatParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  p.style = detail::lineStyle(simulation.scene());
  p.target = glm::uvec4(view.extent.width, view.extent.height, 0u, 0u);
  return p;
}

void checkFrame(uint32_t frame, uint32_t framesInFlight) {
  if (frame >= framesInFlight)
    throw InvalidArgument("frame", "expected a frame slot in [0, " +
                                       std::to_string(framesInFlight - 1) + "], got " +
                                       std::to_string(frame));
}

}  // namespace

void LineRenderer::recordPrepare(VkCommandBuffer commands, uint32_t frame,
                                 const GpuSimulation& simulation, const View& view) {
  const Impl& m = *impl_;
  checkFrame(frame, m.framesInFlight);
  // RAW: step.comp writes the particles, lines.vert or splat.comp reads them.
  detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT);
  if (m.mode != LineMode::Splat) return;
  if (view.extent.width != m.extent.width || view.extent.height != m.extent.height)
    throw InvalidArgument("view.extent", "differs from the renderer's setExtent() (" +
                                             std::to_string(m.extent.width) + "x" +
                                             std::to_string(m.extent.height) + ")");
  const Buffer& sums = m.accumulation[frame];
  // WAR: this slot's last resolve.frag read the sums this fill clears.
  detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, 0);
  m.c.vk.CmdFillBuffer(commands, sums.get(), 0, VK_WHOLE_SIZE, 0);
  // RAW/WAW: splat.comp adds atomically into the cleared sums.
  detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, m.splatPipeline);
  gpu::SplatParams params = splatParams(simulation, view);
  for (const ParticleChunk& chunk : simulation.chunks()) {
    params.target.z = chunk.count;
    detail::PushDescriptors()
        .texels(gpu::kSplatParticleBinding, chunk.texels)
        .buffer(gpu::kSplatSumsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sums.get())
        .push(m.c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, m.splatLayout);
    m.c.vk.CmdPushConstants(commands, m.splatLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                            &params);
    m.c.vk.CmdDispatch(commands, detail::groupCount(chunk.count, gpu::kWorkgroupSize), 1, 1);
  }
  // RAW: resolve.frag reads the sums splat.comp wrote.
  detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT);
}

void LineRenderer::recordDraw(VkCommandBuffer commands, uint32_t frame,
                              const GpuSimulation& simulation, const View& view) const {
  const Impl& m = *impl_;
  checkFrame(frame, m.framesInFlight);
  detail::setViewport(m.c, commands, view.extent);
  if (m.mode == LineMode::Splat) {
    const gpu::SplatParams params = splatParams(simulation, view);
    m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.resolvePipeline);
    detail::PushDescriptors()
        .buffer(gpu::kResolveSumsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                m.accumulation[frame].get())
        .push(m.c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.resolveLayout);
    m.c.vk.CmdPushConstants(commands, m.resolveLayout, VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                            sizeof(params), &params);
    m.c.vk.CmdDraw(commands, 3, 1, 0, 0);
    return;
  }
  gpu::DrawParams params{};
  params.viewProj = glm::make_mat4(view.viewProj.m);
  params.style = detail::lineStyle(simulation.scene());
  m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.linePipeline);
  m.c.vk.CmdPushConstants(commands, m.lineLayout,
                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                          sizeof(params), &params);
  for (const ParticleChunk& chunk : simulation.chunks()) {
    detail::PushDescriptors()
        .buffer(gpu::kParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.buffer, 0,
                VkDeviceSize{chunk.count} * sizeof(Particle))
        .push(m.c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.lineLayout);
    m.c.vk.CmdDraw(commands, 2 * chunk.count, 1, 0, 0);
  }
}

}  // namespace lava
