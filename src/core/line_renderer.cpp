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

// The three passes over a target's color and depth attachments; all compatible, so the
// same pipelines and framebuffers serve each.
enum class PassKind {
  Clear,       // clears the target, then the ground and lines are drawn
  Load,        // keeps what was copied in (the cached ground), then lines are drawn
  Background,  // clears the cache's images and keeps them for copying
};

UniqueRenderPass createRenderPass(VkDevice device, VkFormat colorFormat, PassKind kind,
                                  VkImageLayout finalLayout) {
  const bool load = kind == PassKind::Load;
  const bool background = kind == PassKind::Background;
  VkAttachmentDescription attachments[2] = {};
  attachments[0].format = colorFormat;
  attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[0].loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
  attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[0].initialLayout =
      load ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
  attachments[0].finalLayout = background ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : finalLayout;
  attachments[1] = attachments[0];
  attachments[1].format = LineRenderer::kDepthFormat;
  attachments[1].storeOp =
      background ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].finalLayout = background ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
                                          : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color;
  subpass.pDepthStencilAttachment = &depth;
  VkSubpassDependency dependencies[2] = {};
  // WAW/WAR: the previous frame's pass and read-back used these attachments, and (Load)
  // the copy of the cached ground wrote them or (Background) earlier copies read them.
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                 VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_TRANSFER_WRITE_BIT;
  dependencies[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                 VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dependencies[0].dstAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
  // RAW: the read-back (or, for the cache, the copies into targets) reads what the pass wrote.
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[1].srcStageMask =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dependencies[1].srcAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
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

// Discards `image` into TRANSFER_DST_OPTIMAL for a copy; `after` are the stages and
// accesses that last used it (a previous frame's pass or read-back).
void toTransferDst(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                   VkPipelineStageFlags after, VkAccessFlags written) {
  imageBarrier(commands, image, aspect, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, after, written, VK_PIPELINE_STAGE_TRANSFER_BIT,
               VK_ACCESS_TRANSFER_WRITE_BIT);
}

void copyImage(VkCommandBuffer commands, VkImage from, VkImage to, VkImageAspectFlags aspect,
               VkExtent2D extent) {
  VkImageCopy region{};
  region.srcSubresource = {aspect, 0, 0, 1};
  region.dstSubresource = {aspect, 0, 0, 1};
  region.extent = {extent.width, extent.height, 1};
  vkCmdCopyImage(commands, from, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
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
      colorFormat_(colorFormat),
      cacheable_(copyTargetUsage(context, colorFormat) && copyTargetUsage(context, kDepthFormat)),
      renderPass_(createRenderPass(context.device(), colorFormat, PassKind::Clear, finalLayout)),
      loadPass_(createRenderPass(context.device(), colorFormat, PassKind::Load, finalLayout)),
      backgroundPass_(
          createRenderPass(context.device(), colorFormat, PassKind::Background, finalLayout)),
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

void LineRenderer::drawGround(VkCommandBuffer commands, const gpu::DrawParams& params) {
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout_, 0, 1,
                          &chunks_.front().set, 0, nullptr);
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, groundPipeline_);
  vkCmdPushConstants(commands, pipelineLayout_, stages, 0, sizeof(params), &params);
  vkCmdDraw(commands, kGroundVertices, 1, 0, 0);
}

namespace {

VkClearValue clearColor() {
  VkClearValue clear{};
  clear.color = {{0.012f, 0.010f, 0.018f, 1.0f}};
  return clear;
}

void beginPass(VkCommandBuffer commands, VkRenderPass pass, VkFramebuffer framebuffer,
               VkExtent2D extent) {
  VkClearValue clears[2] = {clearColor(), {}};
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = pass;
  begin.framebuffer = framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(commands, 0, 1, &viewport);
  vkCmdSetScissor(commands, 0, 1, &scissor);
}

}  // namespace

bool LineRenderer::prepareCache(VkCommandBuffer commands, const RenderTarget& target,
                                const gpu::DrawParams& params) {
  GroundCache& c = cache_;
  const bool same = c.extent.width == target.extent.width &&
                    c.extent.height == target.extent.height && c.viewProj == params.viewProj &&
                    c.crater == params.crater;
  if (!same) {  // a new view: drawn directly until it repeats
    c.viewProj = params.viewProj;
    c.crater = params.crater;
    c.drawn = false;
    if (c.extent.width != target.extent.width || c.extent.height != target.extent.height) {
      VK_CHECK(vkDeviceWaitIdle(context_.device()));  // earlier frames may still copy from it
      c.color = {};
      c.depth = {};
      c.framebuffer = {};
      c.extent = target.extent;
    }
    return false;
  }
  if (!cacheable_ || !target.color || !target.depth) return false;
  if (!c.drawn) {
    if (!c.color.image) {
      c.color = createImage(context_, c.extent, colorFormat_,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                            VK_IMAGE_ASPECT_COLOR_BIT);
      c.depth =
          createImage(context_, c.extent, kDepthFormat,
                      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT);
      c.framebuffer = createFramebuffer(context_.device(), backgroundPass_, c.color.view,
                                        c.depth.view, c.extent);
    }
    beginPass(commands, backgroundPass_, c.framebuffer, c.extent);
    drawGround(commands, params);
    vkCmdEndRenderPass(commands);
    c.drawn = true;
  }
  // The target's previous contents are discarded (its last pass or read-back must finish).
  toTransferDst(commands, target.color, VK_IMAGE_ASPECT_COLOR_BIT,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
  toTransferDst(
      commands, target.depth, VK_IMAGE_ASPECT_DEPTH_BIT,
      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  copyImage(commands, c.color.image, target.color, VK_IMAGE_ASPECT_COLOR_BIT, c.extent);
  copyImage(commands, c.depth.image, target.depth, VK_IMAGE_ASPECT_DEPTH_BIT, c.extent);
  return true;
}

void LineRenderer::record(VkCommandBuffer commands, const RenderTarget& target,
                          const OrbitCamera& camera, const Scene& scene,
                          const std::function<void(VkCommandBuffer)>& overlay) {
  const VkExtent2D extent = target.extent;
  // RAW: step.comp writes particles, lines.vert (or splat.comp) reads them.
  memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT);
  const glm::mat4 viewProj = camera.viewProj(float(extent.width) / float(extent.height));
  const glm::vec4 style{scene.lineScale, 8.0f, 5.0f, 0.0f};
  const gpu::SplatParams splat{viewProj, style, glm::uvec4(0u)};
  if (mode_ == LineMode::Splat) splat_.recordSplat(commands, extent, splat);

  gpu::DrawParams params{};
  params.viewProj = viewProj;
  params.style = style;
  params.crater = glm::vec4(scene.emitter, scene.emitterRadius);
  groundCopied_ = prepareCache(commands, target, params);
  beginPass(commands, groundCopied_ ? loadPass_.get() : renderPass_.get(), target.framebuffer,
            extent);
  if (!groundCopied_) drawGround(commands, params);

  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
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
