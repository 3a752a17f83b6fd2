#include "line_renderer.h"

#include "descriptors.h"
#include "ground_frag.h"
#include "ground_vert.h"
#include "lines_frag.h"
#include "lines_vert.h"
#include "pipeline.h"
#include "vk_check.h"

namespace lava {
namespace {

constexpr uint32_t kGroundVertices = 6 + 48 * 6;  // plane + crater quads (ground.vert)

UniqueRenderPass createRenderPass(VkDevice device, VkFormat colorFormat,
                                  VkImageLayout finalLayout) {
  VkAttachmentDescription attachments[2] = {};
  attachments[0].format = colorFormat;
  attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  attachments[0].finalLayout = finalLayout;
  attachments[1] = attachments[0];
  attachments[1].format = LineRenderer::kDepthFormat;
  attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color;
  subpass.pDepthStencilAttachment = &depth;
  VkSubpassDependency dependencies[2] = {};
  // WAW/WAR: the previous frame's pass and read-back used these attachments.
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                 VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[0].srcAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  dependencies[0].dstStageMask =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
  dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
  // RAW: the read-back copy reads what the pass wrote.
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 2;
  info.pAttachments = attachments;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 2;
  info.pDependencies = dependencies;
  VkRenderPass pass = VK_NULL_HANDLE;
  VK_CHECK(vkCreateRenderPass(device, &info, nullptr, &pass));
  return UniqueRenderPass(device, pass);
}

}  // namespace

LineMode parseLineMode(const std::string& source, const std::string& text) {
  if (text == "lines") return LineMode::Pipeline;
  if (text == "splat") return LineMode::Splat;
  throw UsageError(source + ": expected lines or splat, got '" + text + "'");
}

LineRenderer::LineRenderer(Context& context, const GpuSimulator& simulator, VkFormat colorFormat,
                           VkImageLayout finalLayout)
    : context_(context),
      renderPass_(createRenderPass(context.device(), colorFormat, finalLayout)),
      splat_(context, renderPass_, simulator) {
  VkDevice device = context.device();

  setLayout_ = createStorageSetLayout(device, 1, VK_SHADER_STAGE_VERTEX_BIT);
  pipelineLayout_ = createPipelineLayout(device, setLayout_,
                                         VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                         sizeof(gpu::DrawParams));

  GraphicsPipelineDesc ground{kGroundVertSpv, sizeof(kGroundVertSpv), kGroundFragSpv,
                              sizeof(kGroundFragSpv)};
  groundPipeline_ = createGraphicsPipeline(device, pipelineLayout_, renderPass_, ground);
  GraphicsPipelineDesc lines{kLinesVertSpv, sizeof(kLinesVertSpv), kLinesFragSpv,
                             sizeof(kLinesFragSpv)};
  lines.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  lines.additive = true;
  lines.depthWrite = false;  // glowing lines do not occlude
  linePipeline_ = createGraphicsPipeline(device, pipelineLayout_, renderPass_, lines);

  bind(simulator);
}

void LineRenderer::bind(const GpuSimulator& simulator) {
  splat_.bind(simulator);
  VkDevice device = context_.device();
  chunks_.clear();
  const uint32_t count = static_cast<uint32_t>(simulator.chunks().size());
  descriptorPool_ = createStoragePool(device, count, count);
  for (ParticleChunk chunk : simulator.chunks()) {
    chunk.set = allocateSet(device, descriptorPool_, setLayout_);
    writeStorage(device, chunk.set, gpu::kParticleBinding,
                 {chunk.buffer, 0, chunk.count * sizeof(Particle)});
    chunks_.push_back(chunk);
  }
}

void LineRenderer::record(VkCommandBuffer commands, VkFramebuffer framebuffer, VkExtent2D extent,
                          const OrbitCamera& camera, const Scene& scene,
                          const std::function<void(VkCommandBuffer)>& overlay) {
  // RAW: step.comp writes particles, lines.vert (or splat.comp) reads them.
  memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT);
  const glm::mat4 viewProj = camera.viewProj(float(extent.width) / float(extent.height));
  const glm::vec4 style{scene.lineScale, 8.0f, 5.0f, 0.0f};
  const gpu::SplatParams splat{viewProj, style, glm::uvec4(0u)};
  if (mode_ == LineMode::Splat) splat_.recordSplat(commands, extent, splat);

  VkClearValue clears[2] = {};
  clears[0].color = {{0.012f, 0.010f, 0.018f, 1.0f}};
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = renderPass_;
  begin.framebuffer = framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(commands, 0, 1, &viewport);
  vkCmdSetScissor(commands, 0, 1, &scissor);

  gpu::DrawParams params{};
  params.viewProj = viewProj;
  params.style = style;
  params.crater = glm::vec4(scene.emitter, scene.emitterRadius);
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout_, 0, 1,
                          &chunks_.front().set, 0, nullptr);
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, groundPipeline_);
  vkCmdPushConstants(commands, pipelineLayout_, stages, 0, sizeof(params), &params);
  vkCmdDraw(commands, kGroundVertices, 1, 0, 0);

  if (mode_ == LineMode::Splat) {
    splat_.recordResolve(commands, splat);
  } else {
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, linePipeline_);
    for (const ParticleChunk& chunk : chunks_) {
      params.chunk = {chunk.first, 0u, 0u, 0u};
      vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout_, 0, 1,
                              &chunk.set, 0, nullptr);
      vkCmdPushConstants(commands, pipelineLayout_, stages, 0, sizeof(params), &params);
      vkCmdDraw(commands, 2 * chunk.count, 1, 0, 0);
    }
  }
  if (overlay) overlay(commands);
  vkCmdEndRenderPass(commands);
}

}  // namespace lava
