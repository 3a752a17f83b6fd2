// LineRenderer: each alive particle's line, by the graphics pipeline (lines.vert pulls both
// ends from the particle buffer, through its texel view, as a LINE_LIST) or by the splat
// (splat.comp adds every line into fixed-point planes the size of the target and marks the
// tiles it added to; resolve.vert/.frag put the marked tiles over the scene);
// in the lava look, then the glow (glow.comp over cells of the screen, glow.vert/.frag over
// the lit cells only); the flow as one molten surface (surface.comp's passes,
// surface.vert/.frag over the tiles it covers), under the lines.
//
// recordPrepare's passes: one barrier after the simulation; the fills of what the passes
// add into (the splat's sums, the glow's cells and list, the surface's depths, heat, tiles
// and image); one barrier; the glow's splat and the surface's depths (with a flow: one
// barrier, then its heat and splat.comp, which tests against those depths; without:
// splat.comp); one barrier; the glow's light and list, the surface's filter across (one
// barrier, then down); one barrier before the draw. Barriers and dispatches are the fixed
// cost of a frame on a software device (each is a flush of its threads), so there are no
// more than the data flow needs.
#include "lava/renderer.h"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "common/check.h"
#include "common/passes.h"
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

namespace {

constexpr float kShortestLine = 1.25f;  // px: lava at rest stays visible
// Particles the glow adds per frame at most: beyond, every stride-th, its energy times the
// stride (the glow is a blur; a sample of its sources is enough).
constexpr uint32_t kGlowSamples = 16384;
// The share of the molten surface's light that feeds the glow (surface.comp).
constexpr float kRockGlow = 0.3f;
// The stages of the draws' layouts and push constants.
constexpr VkShaderStageFlags kDrawStages =
    VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

// How a pass binds what it reads through a texel view where the device's views hold it, or
// as a storage buffer.
VkDescriptorType readAs(bool texels) {
  return texels ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

// The runs [x, y) of `chunk`'s particles (chunk-local) that no flow emitter owns: lines and
// their glow are the sparks'; the flow is drawn as its molten surface.
std::vector<glm::uvec2> lineRanges(const Scene& scene, const ParticleChunk& chunk) {
  std::vector<glm::uvec2> out;
  uint64_t first = 0;
  for (const Emitter& e : scene.emitters) {
    const uint64_t begin = std::max(first, chunk.first);
    const uint64_t end = std::min(first + e.particles, chunk.first + chunk.count);
    first += e.particles;
    if (e.flow || begin >= end) continue;
    const glm::uvec2 r(uint32_t(begin - chunk.first), uint32_t(end - chunk.first));
    if (!out.empty() && out.back().y == r.x)
      out.back().y = r.y;
    else
      out.push_back(r);
  }
  return out;
}

// Per frame slot, what the glow passes write.
struct GlowSlot {
  Buffer sums, light, list;
  detail::UniqueBufferView lightTexels, sumTexels;  // if cellsAsTexels
};

// Per frame slot, what surface.comp's passes write (shared.h's surface).
struct SurfaceSlot {
  Buffer nearest, hottest, smoothed, marks;
  detail::Image filtered;  // in GENERAL from the slot's first frame on
};

constexpr VkFormat kFilteredFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

}  // namespace

struct LineRenderer::Impl {
  detail::DeviceContext& c;
  RenderFormats formats;
  LineMode mode = LineMode::Lines;
  LookStyle style = LookStyle::Lava;
  LookSettings settings;
  detail::UniqueSampler nearest;
  detail::UniqueDescriptorSetLayout lineSet, splatSet, glowSet, surfaceSet, surfaceDrawSet;
  detail::UniquePipelineLayout lineLayout, splatLayout, glowLayout;
  detail::UniquePipelineLayout surfaceLayout, surfaceDrawLayout;
  detail::UniquePipeline surfacePasses, surfaceDraw;  // the flow as one molten surface
  detail::UniquePipeline plainLines, lavaLines, splatPipeline;
  detail::UniquePipeline glowSplat;
  detail::Image noDepth;  // 1x1, bound when the splat is given no scene depth
  // Bound where the lines (2x1) and the splat (a uint) test against no molten surface (never
  // read).
  detail::Image noSurface;
  Buffer noNearest;
  // The pipelines that read the splat's sums (the resolve; the glow's quads, which may
  // resolve them too) or the glow's cells (its light pass, its quads), for each read through
  // a texel view (setExtent: where the target's fit in one) or as a storage buffer.
  struct Sized {
    bool sumsAsTexels, cellsAsTexels;
    detail::UniqueDescriptorSetLayout resolveSet, glowDrawSet;
    detail::UniquePipelineLayout resolveLayout, glowDrawLayout;
    detail::UniquePipeline plainResolve, lavaResolve, glowDraw;
    detail::UniquePipeline glowResolve;  // the glow's quads resolving the splat's sums too
    detail::UniquePipeline glowLight;
    detail::UniquePipeline glowLightResolve;  // lists the quads over the splat's marked tiles too
  };
  // Built on first need for dynamic rendering; for a render pass, every pair a target can
  // need (cells as buffers only when the sums are too) in the constructor, the only call
  // that reads the host's pass, which the host may destroy and remake at any resize.
  std::vector<std::unique_ptr<Sized>> sizedPipelines;
  const Sized* sized = nullptr;  // setExtent()'s
  // Set-up recorded by the next recordPrepare(): noDepth's and noSurface's first layouts, the glow's
  // quad lists of new slots emptied (a frame's draw may come before any prepare has listed
  // its quads).
  bool depthPending = true;
  std::vector<uint32_t> listsPending;  // slots
  VkExtent2D extent{0, 0};
  glm::uvec2 grid{0, 0};      // glow cells across and down
  glm::uvec2 tiles{0, 0};     // resolve tiles across and down
  VkDeviceSize sumCount = 0;  // the splat's sums for the extent (whole blocks)
  uint32_t used = 1;          // frame slots prepared so far (at least slot 0)
  // Per frame slot in use (recordPrepare() adds a slot on its first use; setExtent()
  // remakes those in use): the splat's sums (and their views, if
  // sumsAsTexels), the resolve tiles lines were added to, and what the glow writes.
  std::vector<Buffer> accumulation;
  std::vector<detail::UniqueBufferView> accumulationTexels;
  std::vector<Buffer> marks;
  std::vector<GlowSlot> glow;
  glm::uvec2 surfaceSize{0, 0};       // surface pixels across and down
  glm::uvec2 surfaceTiles() const {   // their tiles (surface.vert's quads)
    return (surfaceSize + gpu::kSurfaceTile - 1u) / gpu::kSurfaceTile;
  }
  std::vector<SurfaceSlot> surfaces;  // per frame slot, made by its first frame of a flow
  // setSceneDepth(true): the solids' depth per frame slot (made by the slot's first frame at
  // the extent), drawn by a depth-only pass of Lava's own, made on the first need.
  bool ownDepth = false;
  struct SceneDepth {
    detail::Image image;
    detail::UniqueFramebuffer framebuffer;
  };
  std::vector<SceneDepth> sceneDepths;
  detail::UniqueRenderPass depthPass;
  detail::UniquePipelineLayout solidsLayout;
  detail::UniquePipeline solidsDepth;
  // Per frame slot, without push descriptors: recordPrepare() starts the slot's frame.
  mutable std::vector<detail::DescriptorArena> sets;

  Impl(detail::DeviceContext& context, const RenderFormats& f) : c(context), formats(f) {}

  const Sized& sizedFor(bool sumsTexels, bool cellsTexels);
  // Per-slot resources for `count` slots (those for the extent once it is set).
  void grow(uint32_t count);
  void addSizedSlot();
  // Slot `frame`'s sums, bound at `binding` as the draws read them.
  detail::Descriptors& sums(detail::Descriptors& d, uint32_t binding, uint32_t frame) const {
    return sized->sumsAsTexels
               ? d.texels(binding, accumulationTexels[frame])
               : d.buffer(binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, accumulation[frame].get());
  }

  // The lines' two pipelines and the surface's draw, for the host's target.
  void createDrawPipelines(const RenderFormats& target);
  // surface.comp's pipeline and layout.
  void createSurfacePasses();
  // What recordPrepare owes since the last: the no-depth image's layout, the glow lists'
  // first clears.
  void recordPending(VkCommandBuffer commands);
  // The lines through the graphics pipeline, chunk by chunk.
  void recordLines(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                   const View& view) const;
  // The glow's quads (resolving the splat's sums too, when `splat`).
  void recordGlowDraw(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                      const View& view, bool splat) const;
  // The depth pass, with its pipeline of the solids, made once.
  void createDepthPass();
  // Frame slot `frame`'s depth image and framebuffer, made at the first use.
  SceneDepth& depthTarget(uint32_t frame);
  // Records slot `frame`'s scene depth (the solids of the simulation's scene, depth only)
  // and returns its view, in DEPTH_STENCIL_READ_ONLY_OPTIMAL and visible to compute reads.
  VkImageView recordSceneDepth(VkCommandBuffer commands, uint32_t frame,
                               const GpuSimulation& simulation, const View& view);
  // The flow's surface: slot `frame`'s buffers cleared (before the fills' barrier), then
  // its passes (after it; the glow's cells gain the hot rock's light before its light
  // pass); then, in the host's pass, its shading under the lines.
  void recordSurfaceFills(VkCommandBuffer commands, uint32_t frame);
  // Clears what the passes add into (the splat's sums and marks, the glow's cells and list,
  // the surface's depths and heat), and the barrier to the passes.
  void recordFills(VkCommandBuffer commands, uint32_t frame, bool splat, bool glowing, bool flow);
  void recordSurfacePasses(VkCommandBuffer commands, uint32_t frame,
                           const GpuSimulation& simulation, const View& view) const;
  void recordSurfaceFilter(VkCommandBuffer commands, uint32_t frame,
                           const GpuSimulation& simulation, const View& view) const;
  void recordSurface(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                     const View& view) const;
  gpu::SurfaceParams surfaceParams(const GpuSimulation& simulation, const View& view,
                                   uint32_t pass) const;
  // What the lines test against: slot `frame`'s surface, if it has one (`drawn`), its nearest
  // depths (the splat's) and filtered image (the lines'), and its size and margin
  // (DrawParams.surface; 0 for none).
  bool drawn(uint32_t frame, const GpuSimulation& simulation) const;
  glm::vec4 surfaceTest(uint32_t frame, const GpuSimulation& simulation) const;
  void bindSurface(VkCommandBuffer commands, uint32_t frame,
                   const GpuSimulation& simulation) const;
  void recordSplat(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                   const View& view, VkImageView depth) const;
  void bindGlow(VkCommandBuffer commands, uint32_t frame, VkBufferView particles,
                const gpu::GlowParams& params) const;
  void recordGlow(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                  gpu::GlowParams params) const;
  void recordGlowLight(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                       const gpu::GlowParams& params, bool resolves) const;
};

void LineRenderer::Impl::createDrawPipelines(const RenderFormats& target) {
  lineSet = detail::createSetLayout(
      c, {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, kDrawStages);
  lineLayout = detail::createPipelineLayout(c, lineSet, kDrawStages, sizeof(gpu::DrawParams));
  detail::GraphicsPipelineDesc lines{LAVA_SPIRV(spirv::kLinesVertSpv),
                                     LAVA_SPIRV(spirv::kLinesFragSpv), target};
  lines.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  lines.additive = true;
  lines.depthWrite = false;  // glowing lines do not occlude
  plainLines = detail::createGraphicsPipeline(c, lineLayout, lines);
  lines.additive = false;
  lines.screen = true;
  lavaLines = detail::createGraphicsPipeline(c, lineLayout, lines);

  surfaceDrawSet = detail::createSetLayout(
      c, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, kDrawStages);
  surfaceDrawLayout = detail::createPipelineLayout(c, surfaceDrawSet, kDrawStages,
                                                   sizeof(gpu::SurfaceParams));
  detail::GraphicsPipelineDesc surface{LAVA_SPIRV(spirv::kSurfaceVertSpv),
                                       LAVA_SPIRV(spirv::kSurfaceFragSpv), target};
  surface.over = true;
  surface.depthWrite = false;  // the host's depth may be read-only; tested against it only
  surfaceDraw = detail::createGraphicsPipeline(c, surfaceDrawLayout, surface);
}

void LineRenderer::Impl::createSurfacePasses() {
  surfaceSet = detail::createSetLayout(
      c,
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  surfaceLayout = detail::createPipelineLayout(c, surfaceSet, VK_SHADER_STAGE_COMPUTE_BIT,
                                               sizeof(gpu::SurfaceParams));
  surfacePasses = detail::createComputePipeline(
      c, surfaceLayout, LAVA_SPIRV(spirv::kSurfaceCompSpv), {gpu::kWorkgroupSize});
}

LineRenderer::LineRenderer(Device& device, const RenderFormats& formats)
    : impl_(std::make_unique<Impl>(device.context(), formats)) {
  Impl& m = *impl_;
  const detail::DeviceContext& c = m.c;
  detail::checkTarget(c, formats);
  m.nearest = detail::createSampler(c, VK_FILTER_NEAREST);
  m.createDrawPipelines(formats);
  m.createSurfacePasses();
  m.splatSet = detail::createSetLayout(
      c,
      {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT, m.nearest);
  m.splatLayout = detail::createPipelineLayout(c, m.splatSet, VK_SHADER_STAGE_COMPUTE_BIT,
                                               sizeof(gpu::SplatParams));
  // Two pixels per atomic where the device has 64-bit buffer atomics (the same sums).
  m.splatPipeline = detail::createComputePipeline(
      c, m.splatLayout,
      c.handles.int64Atomics ? LAVA_SPIRV(spirv::kSplatPairsSpv) : LAVA_SPIRV(spirv::kSplatCompSpv),
      {gpu::kWorkgroupSize});
  m.glowSet = detail::createSetLayout(
      c,
      {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  m.glowLayout = detail::createPipelineLayout(c, m.glowSet, VK_SHADER_STAGE_COMPUTE_BIT,
                                              sizeof(gpu::GlowParams));
  m.glowSplat = detail::createComputePipeline(c, m.glowLayout, LAVA_SPIRV(spirv::kGlowSplatSpv),
                                              {gpu::kWorkgroupSize});

  m.noNearest = Buffer(c, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device);
  m.noSurface = detail::createImage(c, {2, 1}, kFilteredFormat, VK_IMAGE_USAGE_STORAGE_BIT,
                                    VK_IMAGE_ASPECT_COLOR_BIT);
  m.noDepth =
      detail::createImage(c, {1, 1}, VK_FORMAT_D32_SFLOAT,
                          VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                          VK_IMAGE_ASPECT_DEPTH_BIT);
  if (formats.renderPass) {  // the host's pass is not kept: each pair setExtent() may need
    // (cells as buffers only when the sums are buffers too: there are fewer cells)
    m.sizedFor(true, true);
    m.sizedFor(false, true);
    m.sizedFor(false, false);
    m.formats.renderPass = VK_NULL_HANDLE;
  }
}

LineRenderer::~LineRenderer() = default;

void LineRenderer::setMode(LineMode mode) {
  impl_->mode = mode;
}

LineMode LineRenderer::mode() const {
  return impl_->mode;
}

void LineRenderer::setStyle(LookStyle style) {
  impl_->style = style;
}

LookStyle LineRenderer::style() const {
  return impl_->style;
}

void LineRenderer::setSceneDepth(bool on) {
  impl_->ownDepth = on;
}

bool LineRenderer::sceneDepth() const {
  return impl_->ownDepth;
}

void LineRenderer::Impl::createDepthPass() {
  constexpr VkFormat kDepth = VK_FORMAT_D32_SFLOAT;
  // Cleared, written, left for the splat to sample; it waits for the slot's last splat.
  const VkAttachmentDescription a = common::attachment(
      kDepth, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_UNDEFINED,
      VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
  const VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.pDepthStencilAttachment = &ref;
  constexpr VkPipelineStageFlags kTests =
      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  VkSubpassDependency dependencies[2] = {};
  dependencies[0] = {
      VK_SUBPASS_EXTERNAL,
      0,
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
      kTests,
      0,
      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
      0};
  dependencies[1] = {0,
                     VK_SUBPASS_EXTERNAL,
                     kTests,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                     VK_ACCESS_SHADER_READ_BIT,
                     0};
  const VkRenderPassCreateInfo info = common::onePassInfo(&a, 1, subpass, dependencies, 2);
  VkRenderPass pass = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateRenderPass(c.device(), &info, c.allocator(), &pass));
  depthPass = detail::UniqueRenderPass(c, pass);
  solidsLayout =
      detail::createPipelineLayout(c, VK_NULL_HANDLE, kDrawStages, sizeof(gpu::BackdropParams));
  detail::GraphicsPipelineDesc solids{LAVA_SPIRV(spirv::kGroundVertSpv),
                                      {nullptr, 0},
                                      {VK_FORMAT_UNDEFINED, kDepth, depthPass, 0}};
  solidsDepth = detail::createGraphicsPipeline(c, solidsLayout, solids);
}

LineRenderer::Impl::SceneDepth& LineRenderer::Impl::depthTarget(uint32_t frame) {
  constexpr VkFormat kDepth = VK_FORMAT_D32_SFLOAT;
  if (sceneDepths.size() <= frame) sceneDepths.resize(frame + 1);
  SceneDepth& d = sceneDepths[frame];
  if (!d.image.image) {
    d.image = detail::createImage(
        c, extent, kDepth, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
        VK_IMAGE_ASPECT_DEPTH_BIT);
    const VkImageView attachment = d.image.view;
    const VkFramebufferCreateInfo info =
        common::framebufferInfo(depthPass, &attachment, 1, extent);
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VK_CHECK(c.vk.CreateFramebuffer(c.device(), &info, c.allocator(), &framebuffer));
    d.framebuffer = detail::UniqueFramebuffer(c, framebuffer);
  }
  return d;
}

VkImageView LineRenderer::Impl::recordSceneDepth(VkCommandBuffer commands, uint32_t frame,
                                                 const GpuSimulation& simulation,
                                                 const View& view) {
  if (!depthPass) createDepthPass();
  const SceneDepth& d = depthTarget(frame);
  VkClearValue clear{};
  clear.depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = depthPass;
  begin.framebuffer = d.framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = 1;
  begin.pClearValues = &clear;
  c.vk.CmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);
  detail::setViewport(c, commands, extent);
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, solidsDepth);
  const Scene& scene = simulation.scene();
  gpu::BackdropParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  const Emitter& vent = scene.emitters.at(0);
  p.vent = {vent.position.x, vent.position.y, vent.position.z, vent.radius};
  p.eye = {view.eye.x, view.eye.y, view.eye.z, gpu::kLookLava};
  detail::recordSolids(c, commands, solidsLayout, scene, p);
  c.vk.CmdEndRenderPass(commands);
  return d.image.view;
}

void LineRenderer::setSettings(const LookSettings& s) {
  if (!(s.exposure > 0.0f && s.exposure <= 16.0f))
    throw InvalidArgument("exposure", "expected (0, 16], got " + std::to_string(s.exposure));
  if (!(s.bloom >= 0.0f && s.bloom <= 4.0f))
    throw InvalidArgument("bloom", "expected [0, 4], got " + std::to_string(s.bloom));
  if (!(s.threshold >= 0.0f && s.threshold <= 16.0f))
    throw InvalidArgument("threshold", "expected [0, 16], got " + std::to_string(s.threshold));
  impl_->settings = s;
}

const LookSettings& LineRenderer::settings() const {
  return impl_->settings;
}

// Sized's pipelines for sums and cells read through texel views or as storage buffers.
const LineRenderer::Impl::Sized& LineRenderer::Impl::sizedFor(bool sumsTexels, bool cellsTexels) {
  for (const std::unique_ptr<Sized>& built : sizedPipelines)
    if (built->sumsAsTexels == sumsTexels && built->cellsAsTexels == cellsTexels) return *built;
  auto p = std::make_unique<Sized>();
  Sized& z = *p;
  z.sumsAsTexels = sumsTexels;
  z.cellsAsTexels = cellsTexels;
  z.resolveSet = detail::createSetLayout(c, {readAs(sumsTexels), VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                         kDrawStages);
  z.resolveLayout =
      detail::createPipelineLayout(c, z.resolveSet, kDrawStages, sizeof(gpu::SplatParams));
  detail::GraphicsPipelineDesc resolve{
      LAVA_SPIRV(spirv::kResolveVertSpv),
      sumsTexels ? LAVA_SPIRV(spirv::kResolveFragSpv) : LAVA_SPIRV(spirv::kResolveBufferFragSpv),
      formats};
  resolve.additive = true;
  resolve.depthTest = false;
  resolve.depthWrite = false;
  z.plainResolve = detail::createGraphicsPipeline(c, z.resolveLayout, resolve);
  resolve.additive = false;
  resolve.screen = true;
  z.lavaResolve = detail::createGraphicsPipeline(c, z.resolveLayout, resolve);

  z.glowDrawSet = detail::createSetLayout(
      c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, readAs(cellsTexels), readAs(sumsTexels)}, kDrawStages);
  z.glowDrawLayout =
      detail::createPipelineLayout(c, z.glowDrawSet, kDrawStages, sizeof(gpu::GlowParams));
  detail::GraphicsPipelineDesc quads{
      cellsTexels ? LAVA_SPIRV(spirv::kGlowVertSpv) : LAVA_SPIRV(spirv::kGlowVertBufferSpv),
      LAVA_SPIRV(spirv::kGlowFragSpv), formats};
  quads.screen = true;
  quads.depthTest = false;
  quads.depthWrite = false;
  z.glowDraw = detail::createGraphicsPipeline(c, z.glowDrawLayout, quads);
  quads.frag = sumsTexels ? LAVA_SPIRV(spirv::kGlowResolveFragSpv)
                          : LAVA_SPIRV(spirv::kGlowResolveBufferFragSpv);
  z.glowResolve = detail::createGraphicsPipeline(c, z.glowDrawLayout, quads);

  const detail::Spirv light =
      cellsTexels ? LAVA_SPIRV(spirv::kGlowLightSpv) : LAVA_SPIRV(spirv::kGlowLightBufferSpv);
  z.glowLight =
      detail::createComputePipeline(c, glowLayout, light, {gpu::kWorkgroupSize, VK_FALSE});
  z.glowLightResolve =
      detail::createComputePipeline(c, glowLayout, light, {gpu::kWorkgroupSize, VK_TRUE});
  sizedPipelines.push_back(std::move(p));
  return z;
}

void LineRenderer::setExtent(VkExtent2D extent) {
  Impl& m = *impl_;
  if (extent.width == m.extent.width && extent.height == m.extent.height) return;
  if (extent.width == 0 || extent.height == 0)
    throw InvalidArgument("extent", "expected a non-empty size");
  m.sets.clear();  // sets of the old layouts name the old buffers
  m.sceneDepths.clear();
  m.accumulationTexels.clear();
  m.accumulation.clear();
  m.marks.clear();
  m.glow.clear();
  m.surfaces.clear();
  m.listsPending.clear();
  m.surfaceSize = {(extent.width + gpu::kSurfaceScale - 1) / gpu::kSurfaceScale,
                   (extent.height + gpu::kSurfaceScale - 1) / gpu::kSurfaceScale};
  m.grid = {(extent.width + gpu::kGlowCell - 1) / gpu::kGlowCell,
            (extent.height + gpu::kGlowCell - 1) / gpu::kGlowCell};
  const VkDeviceSize cells = VkDeviceSize{m.grid.x} * m.grid.y;
  m.tiles = {detail::groupCount(extent.width, gpu::kResolveTile),
             detail::groupCount(extent.height, gpu::kResolveTile)};
  m.sumCount = VkDeviceSize{detail::groupCount(extent.width, gpu::kSplatBlockWidth)} *
               detail::groupCount(extent.height, gpu::kSplatBlockHeight) * gpu::kSplatBlockWidth *
               gpu::kSplatBlockHeight;
  // The draws read the sums through a texel view where one holds them (on llvmpipe a
  // gather, where a storage-buffer load is a loop over the lanes); 720p needs 921,600
  // texels, more than the spec's minimum of 65,536.
  const bool sumTexels = m.sumCount <= m.c.limits.maxTexelBufferElements;
  // The glow's cells the same (the minimum holds 4K's 32,400 cells, not 8K's 129,600).
  const bool cellTexels = cells <= m.c.limits.maxTexelBufferElements;
  m.sized = &m.sizedFor(sumTexels, cellTexels);
  m.extent = extent;
  m.grow(m.used);
}

void LineRenderer::Impl::grow(uint32_t count) {
  while (sets.size() < count) sets.emplace_back(c);
  if (extent.width == 0) return;
  while (accumulation.size() < count) addSizedSlot();
}

void LineRenderer::Impl::addSizedSlot() {
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  accumulation.emplace_back(
      c, sumCount * sizeof(uint32_t),
      storage | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
          (sized->sumsAsTexels ? VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT : 0),
      detail::MemoryUse::Device);
  if (sized->sumsAsTexels)
    accumulationTexels.push_back(
        detail::createTexelView(c, accumulation.back().get(), VK_WHOLE_SIZE, VK_FORMAT_R32_UINT));
  marks.emplace_back(c, VkDeviceSize{tiles.x} * tiles.y * sizeof(uint32_t),
                     storage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, detail::MemoryUse::Device);
  const VkDeviceSize cells = VkDeviceSize{grid.x} * grid.y;
  GlowSlot g;
  const VkBufferUsageFlags cellUse =
      storage | (sized->cellsAsTexels ? VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT : 0);
  g.sums = Buffer(c, 2 * cells * sizeof(uint32_t), cellUse | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  detail::MemoryUse::Device);
  g.light = Buffer(c, cells * 2 * sizeof(float), cellUse, detail::MemoryUse::Device);
  if (sized->cellsAsTexels) {
    g.sumTexels = detail::createTexelView(c, g.sums.get(), VK_WHOLE_SIZE, VK_FORMAT_R32G32_UINT);
    g.lightTexels =
        detail::createTexelView(c, g.light.get(), VK_WHOLE_SIZE, VK_FORMAT_R32G32_SFLOAT);
  }
  const VkDeviceSize quads = VkDeviceSize{grid.x + 1} * (grid.y + 1);
  g.list = Buffer(c, 16 + quads * sizeof(uint32_t),
                  storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                  detail::MemoryUse::Device);
  glow.push_back(std::move(g));
  listsPending.push_back(static_cast<uint32_t>(glow.size() - 1));
}

namespace {

gpu::SplatParams splatParams(const GpuSimulation& simulation, const View& view, LookStyle style,
                             const LookSettings& settings) {
  gpu::SplatParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  p.style = detail::lineStyle(simulation.scene(), style);
  p.target = glm::uvec4(view.extent.width, view.extent.height, 0u, 0u);
  p.look = glm::vec4(settings.exposure, 0.0f, 0.0f, 0.0f);
  return p;
}

gpu::GlowParams glowParams(const GpuSimulation& simulation, const View& view,
                           const LookSettings& settings, glm::uvec2 grid) {
  gpu::GlowParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  p.style = detail::lineStyle(simulation.scene(), LookStyle::Lava);
  const uint64_t particles = simulation.scene().particles();
  const uint32_t stride = static_cast<uint32_t>((particles + kGlowSamples - 1) / kGlowSamples);
  p.grid = glm::uvec4(grid.x, grid.y, 0u, std::max(stride, 1u));
  p.target = glm::uvec4(view.extent.width, view.extent.height, 0u, 0u);
  p.glow = glm::vec4(settings.threshold, settings.bloom, settings.exposure, 0.0f);
  return p;
}

}  // namespace

namespace {

// The first flow emitter's rest spacing (m).
float restSpacing(const Scene& scene) {
  for (const Emitter& e : scene.emitters)
    if (e.flow) return std::cbrt(e.mass / scene.flow->density);
  return scene.flow->radius * 0.5f;
}

}  // namespace

bool LineRenderer::Impl::drawn(uint32_t frame, const GpuSimulation& simulation) const {
  return simulation.flowBuffers().slots > 0 && frame < surfaces.size() &&
         surfaces[frame].nearest.get() != VK_NULL_HANDLE;
}

glm::vec4 LineRenderer::Impl::surfaceTest(uint32_t frame, const GpuSimulation& simulation) const {
  if (!drawn(frame, simulation)) return glm::vec4(0.0f);
  // A spark within a sphere and a half of the surface's front is not behind it.
  return {float(surfaceSize.x), float(surfaceSize.y), 1.5f * restSpacing(simulation.scene()),
          0.0f};
}

gpu::SurfaceParams LineRenderer::Impl::surfaceParams(const GpuSimulation& simulation,
                                                     const View& view, uint32_t pass) const {
  const Scene& scene = simulation.scene();
  const float spacing = restSpacing(scene);
  gpu::SurfaceParams p{};
  p.viewProj = glm::make_mat4(view.viewProj.m);
  // Spheres one rest spacing in radius: neighbours overlap, and a settled layer has no gaps.
  p.heat = {scene.flow->solidus, scene.flow->temperature, scene.flow->ambient, spacing};
  const bool glowOn = style == LookStyle::Lava && settings.bloom > 0.0f;
  // The glow's fixed point (glow.comp's kFixed) times the share of the rock's light that
  // spreads: a pool is far larger than a spark, and all of its light would wash out the scene.
  p.look = {settings.exposure, glowOn ? 256.0f * kRockGlow : 0.0f, spacing,
            float(view.extent.height)};
  p.eye = {view.eye.x, view.eye.y, view.eye.z, float(view.extent.width)};
  p.size = {surfaceSize.x, surfaceSize.y, pass, simulation.flowBuffers().slots};
  return p;
}

void LineRenderer::Impl::recordSurfaceFills(VkCommandBuffer commands, uint32_t frame) {
  if (surfaces.size() <= frame) surfaces.resize(frame + 1);
  SurfaceSlot& slot = surfaces[frame];
  const VkDeviceSize pixels = VkDeviceSize{surfaceSize.x} * surfaceSize.y;
  const VkBufferUsageFlags use =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if (!slot.nearest.get()) {
    slot.nearest = Buffer(c, pixels * sizeof(uint32_t), use, detail::MemoryUse::Device);
    slot.hottest = Buffer(c, pixels * 4 * sizeof(uint32_t), use, detail::MemoryUse::Device);
    slot.marks = Buffer(c, VkDeviceSize{surfaceTiles().x} * surfaceTiles().y * sizeof(uint32_t),
                        use, detail::MemoryUse::Device);
    slot.smoothed = Buffer(c, pixels * sizeof(gpu::SmoothPixel),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device);
    slot.filtered = detail::createImage(
        c, {2 * surfaceSize.x, surfaceSize.y}, kFilteredFormat,
        VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    // GENERAL for good: cleared, then the down pass writes it and the draws read it.
    detail::imageBarrier(c, commands, slot.filtered.image, VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_ACCESS_TRANSFER_WRITE_BIT);
  }
  // Empty where no sphere's tile is (the down pass writes the touched tiles only).
  const VkClearColorValue empty{};
  const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  c.vk.CmdClearColorImage(commands, slot.filtered.image, VK_IMAGE_LAYOUT_GENERAL, &empty, 1, &all);
  c.vk.CmdFillBuffer(commands, slot.nearest.get(), 0, VK_WHOLE_SIZE, gpu::kSurfaceEmpty);
  c.vk.CmdFillBuffer(commands, slot.hottest.get(), 0, VK_WHOLE_SIZE, 0);
  c.vk.CmdFillBuffer(commands, slot.marks.get(), 0, VK_WHOLE_SIZE, 0);
}

void LineRenderer::Impl::bindSurface(VkCommandBuffer commands, uint32_t frame,
                                     const GpuSimulation& simulation) const {
  const GpuSimulation::FlowBuffers flow = simulation.flowBuffers();
  const SurfaceSlot& slot = surfaces[frame];
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, surfacePasses);
  detail::Descriptors()
      .buffer(gpu::kSurfaceParticleBinding, kStorage, flow.particles)
      .buffer(gpu::kSurfaceHeatBinding, kStorage, flow.heat)
      .buffer(gpu::kSurfaceDepthBinding, kStorage, slot.nearest.get())
      .buffer(gpu::kSurfaceHottestBinding, kStorage, slot.hottest.get())
      .buffer(gpu::kSurfaceSmoothBinding, kStorage, slot.smoothed.get())
      .buffer(gpu::kSurfaceGlowBinding, kStorage, glow[frame].sums.get())
      .image(gpu::kSurfaceImageBinding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, slot.filtered.view,
             VK_IMAGE_LAYOUT_GENERAL)
      .buffer(gpu::kSurfaceMarksBinding, kStorage, slot.marks.get())
      .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, surfaceLayout, surfaceSet, sets[frame]);
}

void LineRenderer::Impl::recordSurfacePasses(VkCommandBuffer commands, uint32_t frame,
                                             const GpuSimulation& simulation,
                                             const View& view) const {
  bindSurface(commands, frame, simulation);
  const uint32_t slots = simulation.flowBuffers().slots;
  for (const uint32_t pass : {gpu::kSurfacePassDepth, gpu::kSurfacePassHeat}) {
    if (pass == gpu::kSurfacePassHeat)  // RAW: the heat pass reads the nearest depths
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    const gpu::SurfaceParams params = surfaceParams(simulation, view, pass);
    c.vk.CmdPushConstants(commands, surfaceLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                          &params);
    c.vk.CmdDispatch(commands, detail::groupCount(slots, gpu::kWorkgroupSize), 1, 1);
  }
}

void LineRenderer::Impl::recordSurfaceFilter(VkCommandBuffer commands, uint32_t frame,
                                             const GpuSimulation& simulation,
                                             const View& view) const {
  bindSurface(commands, frame, simulation);  // the glow's light pass bound its own
  const uint32_t tileCount = surfaceTiles().x * surfaceTiles().y;
  for (const uint32_t pass : {gpu::kSurfacePassAcross, gpu::kSurfacePassDown}) {
    if (pass == gpu::kSurfacePassDown)  // RAW: down reads what across wrote
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_READ_BIT);
    const gpu::SurfaceParams params = surfaceParams(simulation, view, pass);
    c.vk.CmdPushConstants(commands, surfaceLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                          &params);
    c.vk.CmdDispatch(commands, tileCount, 1, 1);  // a workgroup a tile
  }
}

void LineRenderer::Impl::recordSurface(VkCommandBuffer commands, uint32_t frame,
                                       const GpuSimulation& simulation, const View& view) const {
  if (!drawn(frame, simulation)) return;
  const gpu::SurfaceParams params = surfaceParams(simulation, view, 0);
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, surfaceDraw);
  detail::Descriptors()
      .image(gpu::kSurfaceDrawBinding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
             surfaces[frame].filtered.view, VK_IMAGE_LAYOUT_GENERAL)
      .buffer(gpu::kSurfaceDrawMarksBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
              surfaces[frame].marks.get())
      .bind(c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, surfaceDrawLayout, surfaceDrawSet,
            sets[frame]);
  c.vk.CmdPushConstants(commands, surfaceDrawLayout, kDrawStages, 0, sizeof(params), &params);
  c.vk.CmdDraw(commands, 6 * surfaceTiles().x * surfaceTiles().y, 1, 0, 0);
}

void LineRenderer::Impl::recordSplat(VkCommandBuffer commands, uint32_t frame,
                                     const GpuSimulation& simulation, const View& view,
                                     VkImageView depth) const {
  const Buffer& sums = accumulation[frame];  // recordPrepare cleared them and the marks
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, splatPipeline);
  gpu::SplatParams params = splatParams(simulation, view, style, settings);
  params.target.w = depth ? 1u : 0u;
  const glm::vec4 surface = surfaceTest(frame, simulation);
  params.look = {params.look.x, surface.x, surface.y, surface.z};
  for (const ParticleChunk& chunk : simulation.chunks()) {
    const std::vector<glm::uvec2> ranges = lineRanges(simulation.scene(), chunk);
    if (ranges.empty()) continue;
    detail::Descriptors()
        .texels(gpu::kSplatParticleBinding, chunk.texels)
        .buffer(gpu::kSplatSumsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sums.get())
        .image(gpu::kSplatDepthBinding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
               depth ? depth : noDepth.view.get(), VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL)
        .buffer(gpu::kSplatMarksBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, marks[frame].get())
        .buffer(gpu::kSplatSurfaceBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                drawn(frame, simulation) ? surfaces[frame].nearest.get() : noNearest.get())
        .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, splatLayout, splatSet, sets[frame]);
    for (const glm::uvec2& r : ranges) {
      params.range.x = r.x;
      params.target.z = r.y;
      c.vk.CmdPushConstants(commands, splatLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                            &params);
      c.vk.CmdDispatch(commands, detail::groupCount(r.y - r.x, gpu::kWorkgroupSize), 1, 1);
    }
  }
}

// glow.comp's bindings (both passes: `particles` is the splat's chunk) and parameters.
void LineRenderer::Impl::bindGlow(VkCommandBuffer commands, uint32_t frame, VkBufferView particles,
                                  const gpu::GlowParams& params) const {
  const GlowSlot& g = glow[frame];
  detail::Descriptors descriptors;
  descriptors.texels(gpu::kGlowParticlesBinding, particles)
      .buffer(gpu::kGlowSumsBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.sums.get())
      .buffer(gpu::kGlowLightBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.light.get())
      .buffer(gpu::kGlowListBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.list.get())
      .buffer(gpu::kGlowMarksBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, marks[frame].get());
  // Without texel views of the cells the light pass reads the sums' buffer (binding 1) and
  // no module uses this binding.
  if (sized->cellsAsTexels) descriptors.texels(gpu::kGlowSumTexelsBinding, g.sumTexels);
  descriptors.bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, glowLayout, glowSet, sets[frame]);
  c.vk.CmdPushConstants(commands, glowLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                        &params);
}

void LineRenderer::Impl::recordGlow(VkCommandBuffer commands, uint32_t frame,
                                    const GpuSimulation& simulation, gpu::GlowParams params) const {
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, glowSplat);  // sums cleared
  const uint32_t stride = params.grid.w;
  params.target.z = 1;  // the first chunk's splat resets the list
  for (const ParticleChunk& chunk : simulation.chunks()) {
    for (const glm::uvec2& r : lineRanges(simulation.scene(), chunk)) {
      if (params.target.z == 0)  // after the first dispatch: its adds before this one's
        detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                              VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                              VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
      params.grid.z = r.y;
      params.target.w = r.x;
      bindGlow(commands, frame, chunk.texels, params);
      c.vk.CmdDispatch(
          commands,
          detail::groupCount((uint64_t{r.y - r.x} + stride - 1) / stride, gpu::kWorkgroupSize), 1,
          1);
      params.target.z = 0;
    }
  }
}

void LineRenderer::Impl::recordGlowLight(VkCommandBuffer commands, uint32_t frame,
                                         const GpuSimulation& simulation,
                                         const gpu::GlowParams& params, bool resolves) const {
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE,
                       resolves ? sized->glowLightResolve : sized->glowLight);
  bindGlow(commands, frame, simulation.chunks().front().texels, params);
  // One workgroup per tile of quads (there is one quad more than cells across and down).
  c.vk.CmdDispatch(commands, grid.x / gpu::kGlowTile + 1, grid.y / gpu::kGlowTile + 1, 1);
}

void LineRenderer::Impl::recordPending(VkCommandBuffer commands) {
  if (depthPending) {
    detail::imageBarrier(c, commands, noDepth.image, VK_IMAGE_ASPECT_DEPTH_BIT,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_ACCESS_SHADER_READ_BIT);
    detail::imageBarrier(c, commands, noSurface.image, VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                         VK_ACCESS_SHADER_READ_BIT);
    depthPending = false;
  }
  if (listsPending.empty()) return;
  for (const uint32_t slot : listsPending)
    c.vk.CmdFillBuffer(commands, glow[slot].list.get(), 0, 16, 0);
  // RAW: the glow's draw reads the lists as indirect arguments; WAW: the glow's passes
  // count into them.
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT |
                            VK_ACCESS_SHADER_WRITE_BIT);
  listsPending.clear();
}

void LineRenderer::Impl::recordFills(VkCommandBuffer commands, uint32_t frame, bool splat,
                                     bool glowing, bool flow) {
  if (splat) {
    c.vk.CmdFillBuffer(commands, accumulation[frame].get(), 0, VK_WHOLE_SIZE, 0);
    c.vk.CmdFillBuffer(commands, marks[frame].get(), 0, VK_WHOLE_SIZE, 0);
  }
  if (glowing) {
    c.vk.CmdFillBuffer(commands, glow[frame].sums.get(), 0, VK_WHOLE_SIZE, 0);
    // The list's draw arguments, no quads yet (a flow without sparks has no glow splat to
    // reset them).
    const uint32_t none[4] = {0, 1, 0, 0};
    c.vk.CmdUpdateBuffer(commands, glow[frame].list.get(), 0, sizeof(none), none);
  }
  if (flow) recordSurfaceFills(commands, frame);
  // RAW/WAW: splat.comp, glow.comp and surface.comp add atomically into the cleared sums,
  // depths and heat (splat.comp marks tiles too).
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void LineRenderer::recordPrepare(VkCommandBuffer commands, uint32_t frame,
                                 const GpuSimulation& simulation, const View& view,
                                 VkImageView depth) {
  Impl& m = *impl_;
  m.c.checkFrame(frame);
  m.used = std::max(m.used, frame + 1);
  m.grow(m.used);
  simulation.recordInit(commands);
  m.recordPending(commands);
  const bool splat = m.mode == LineMode::Splat;
  const bool glow = m.style == LookStyle::Lava && m.settings.bloom > 0.0f;
  const bool flow = simulation.flowBuffers().slots > 0;
  if ((splat || glow || flow) &&
      (view.extent.width != m.extent.width || view.extent.height != m.extent.height))
    throw InvalidArgument("view.extent", "differs from the renderer's setExtent() (" +
                                             std::to_string(m.extent.width) + "x" +
                                             std::to_string(m.extent.height) + ")");
  // RAW: step.comp writes the particles, lines.vert, splat.comp or glow.comp reads them.
  // WAR/WAW: this slot's last frame read (resolve.frag, glow.comp, the glow's draw, as its
  // indirect arguments too) and wrote what the fills clear and the passes rewrite.
  detail::memoryBarrier(
      m.c, commands,
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
          VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
      VK_ACCESS_SHADER_WRITE_BIT,
      VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
          VK_PIPELINE_STAGE_TRANSFER_BIT,
      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
  m.sets[frame].reset();  // the slot's previous frame has finished
  if (!splat && !glow && !flow) return;
  m.recordFills(commands, frame, splat, glow, flow);
  if (splat && !depth && m.ownDepth) depth = m.recordSceneDepth(commands, frame, simulation, view);
  const gpu::GlowParams params = glowParams(simulation, view, m.settings, m.grid);
  if (glow) m.recordGlow(commands, frame, simulation, params);
  if (flow) m.recordSurfacePasses(commands, frame, simulation, view);
  // After the surface's depth pass and the barrier behind it: the splat leaves out the lines
  // behind the rock.
  if (splat) m.recordSplat(commands, frame, simulation, view, depth);
  // RAW: the light pass reads the cells the splats added; it counts into the list's
  // arguments. The surface's filter reads its depths and heat.
  if (glow || flow)
    detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  if (glow) m.recordGlowLight(commands, frame, simulation, params, splat);  // resolves the splat
  if (flow) m.recordSurfaceFilter(commands, frame, simulation, view);
  // RAW: resolve.vert reads the marks, resolve.frag the splat's sums; the glow's draw reads
  // the list (its arguments too) and the light (and the splat's sums, when it resolves them);
  // surface.frag the filtered surface.
  detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                            VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                        VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
}

void LineRenderer::recordDraw(VkCommandBuffer commands, uint32_t frame,
                              const GpuSimulation& simulation, const View& view) const {
  const Impl& m = *impl_;
  m.c.checkFrame(frame);
  if (frame >= m.sets.size())
    throw InvalidArgument("frame", "slot " + std::to_string(frame) +
                                       " has had no recordPrepare() yet: prepare it first");
  detail::setViewport(m.c, commands, view.extent);
  const bool lava = m.style == LookStyle::Lava;
  const bool glow = lava && m.settings.bloom > 0.0f;
  const bool splat = m.mode == LineMode::Splat;
  m.recordSurface(commands, frame, simulation, view);
  // The lines: the graphics pipeline's, or the splat's sums resolved over its marked tiles.
  // With the glow on, the glow's quads resolve the sums instead (below), in their own pass:
  // one blend a pixel where two passes would take two.
  if (!splat) {
    m.recordLines(commands, frame, simulation, view);
  } else if (!glow) {
    const gpu::SplatParams params = splatParams(simulation, view, m.style, m.settings);
    m.c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS,
                           lava ? m.sized->lavaResolve : m.sized->plainResolve);
    detail::Descriptors descriptors;
    m.sums(descriptors, gpu::kResolveSumsBinding, frame)
        .buffer(gpu::kResolveMarksBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m.marks[frame].get())
        .bind(m.c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m.sized->resolveLayout,
              m.sized->resolveSet, m.sets[frame]);
    m.c.vk.CmdPushConstants(commands, m.sized->resolveLayout, kDrawStages, 0, sizeof(params),
                            &params);
    m.c.vk.CmdDraw(commands, 6 * m.tiles.x * m.tiles.y, 1, 0, 0);
  }
  if (glow) m.recordGlowDraw(commands, frame, simulation, view, splat);
}

void LineRenderer::Impl::recordLines(VkCommandBuffer commands, uint32_t frame,
                                     const GpuSimulation& simulation, const View& view) const {
  gpu::DrawParams params{};
  params.viewProj = glm::make_mat4(view.viewProj.m);
  params.style = detail::lineStyle(simulation.scene(), style);
  params.target = {float(view.extent.width), float(view.extent.height), settings.exposure,
                   kShortestLine};
  params.surface = surfaceTest(frame, simulation);
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS,
                       style == LookStyle::Lava ? lavaLines : plainLines);
  c.vk.CmdPushConstants(commands, lineLayout, kDrawStages, 0, sizeof(params), &params);
  for (const ParticleChunk& chunk : simulation.chunks()) {
    const std::vector<glm::uvec2> ranges = lineRanges(simulation.scene(), chunk);
    if (ranges.empty()) continue;
    detail::Descriptors()
        .texels(gpu::kParticleBinding, chunk.texels)
        .image(gpu::kLineSurfaceBinding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
               drawn(frame, simulation) ? surfaces[frame].filtered.view : noSurface.view,
               VK_IMAGE_LAYOUT_GENERAL)
        .bind(c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, lineLayout, lineSet, sets[frame]);
    for (const glm::uvec2& r : ranges) c.vk.CmdDraw(commands, 2 * (r.y - r.x), 1, 2 * r.x, 0);
  }
}

void LineRenderer::Impl::recordGlowDraw(VkCommandBuffer commands, uint32_t frame,
                                        const GpuSimulation& simulation, const View& view,
                                        bool splat) const {
  const GlowSlot& g = glow[frame];
  const gpu::GlowParams params = glowParams(simulation, view, settings, grid);
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS,
                       splat ? sized->glowResolve : sized->glowDraw);
  detail::Descriptors descriptors;
  descriptors.buffer(gpu::kGlowDrawListBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.list.get());
  if (sized->cellsAsTexels)
    descriptors.texels(gpu::kGlowDrawLightBinding, g.lightTexels);
  else
    descriptors.buffer(gpu::kGlowDrawLightBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       g.light.get());
  if (splat) sums(descriptors, gpu::kGlowDrawSumsBinding, frame);
  descriptors.bind(c, commands, VK_PIPELINE_BIND_POINT_GRAPHICS, sized->glowDrawLayout,
                   sized->glowDrawSet, sets[frame]);
  c.vk.CmdPushConstants(commands, sized->glowDrawLayout, kDrawStages, 0, sizeof(params), &params);
  c.vk.CmdDrawIndirect(commands, g.list.get(), 0, 1, sizeof(VkDrawIndirectCommand));
}

}  // namespace lava
