#include "frame_renderer.h"

#include <cstring>

#include "common/passes.h"
#include "common/steps.h"
#include "series.h"

namespace lava::host {
namespace {

constexpr VkImageAspectFlags kColor = VK_IMAGE_ASPECT_COLOR_BIT;
constexpr VkImageAspectFlags kDepth = VK_IMAGE_ASPECT_DEPTH_BIT;
constexpr VkPipelineStageFlags kDepthStages =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
constexpr VkPipelineStageFlags kColorStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;

// What the backdrop is drawn from: the view and every input of Backdrop::recordDraw. The
// cached backdrop is redrawn when any of it changes.
std::vector<float> backdropKey(const View& view, const Scene& scene, LookStyle style) {
  std::vector<float> key(view.viewProj.m, view.viewProj.m + 16);
  key.push_back(style == LookStyle::Lava ? 1.0f : 0.0f);
  key.insert(key.end(), {view.eye.x, view.eye.y, view.eye.z});
  const Emitter& e = scene.emitters.at(0);
  key.insert(key.end(),
             {e.position.x, e.position.y, e.position.z, e.radius, float(int(e.shape))});
  for (const Collider& c : scene.colliders)
    key.insert(key.end(), {float(int(c.type)), c.position.x, c.position.y, c.position.z,
                           c.normal.x, c.normal.y, c.normal.z, c.radius, c.size.x, c.size.y,
                           c.size.z, c.baseRadius, c.topRadius, c.height});
  return key;
}

bool sameKey(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}
// Discards `image` into `to` for its first use this frame; the previous frame's pass or
// copy (WAW) and read-back (WAR) of it come first.
void discardInto(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect,
                 VkImageLayout to, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  const bool color = aspect == kColor;
  imageBarrier(commands, image, aspect, VK_IMAGE_LAYOUT_UNDEFINED, to,
               (color ? kColorStage : kDepthStages) | VK_PIPELINE_STAGE_TRANSFER_BIT,
               (color ? VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT
                      : VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT) |
                   VK_ACCESS_TRANSFER_WRITE_BIT,
               dstStage, dstAccess);
}

void toAttachment(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect) {
  const bool color = aspect == kColor;
  discardInto(
      commands, image, aspect,
      color ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
      color ? kColorStage : kDepthStages,
      color ? VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT
            : VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
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

template <typename F>
F deviceFunction(const Device& device, const char* name, const char* khr) {
  VkDevice handle = device.handles().device;
  auto f = reinterpret_cast<F>(vkGetDeviceProcAddr(handle, name));
  if (!f) f = reinterpret_cast<F>(vkGetDeviceProcAddr(handle, khr));
  if (!f) throw ResourceError(std::string("the device has no ") + name);
  return f;
}

}  // namespace

FrameRenderer::FrameRenderer(Device& device, VkFormat colorFormat, LookStyle style)
    : device_(device),
      colorFormat_(colorFormat),
      backdrop_(device, {colorFormat, kDepthFormat}),
      lines_(device, {colorFormat, kDepthFormat}),
      cmdBeginRendering_(deviceFunction<PFN_vkCmdBeginRendering>(device, "vkCmdBeginRendering",
                                                                 "vkCmdBeginRenderingKHR")),
      cmdEndRendering_(deviceFunction<PFN_vkCmdEndRendering>(device, "vkCmdEndRendering",
                                                             "vkCmdEndRenderingKHR")) {
  lines_.setStyle(style);
}

// `load`: the lines' pass over the backdrop, its depth tested against but kept (read-only,
// as the splat samples it); else the backdrop's pass, cleared.
void FrameRenderer::beginRendering(VkCommandBuffer commands, VkImageView color, VkImageView depth,
                                   VkExtent2D extent, bool load) const {
  common::beginFramePass(cmdBeginRendering_, commands, color, depth, extent, load,
                         {{0.012f, 0.010f, 0.018f, 1.0f}},
                         VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
}

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  device_.waitIdle();  // frames in flight may still read the per-size resources
  lines_.setExtent(extent);
  cache_ = {};
  extent_ = extent;
}

bool FrameRenderer::copyBackdrop(VkCommandBuffer commands, uint32_t frame,
                                 const FrameTarget& target, const View& view, const Scene& scene) {
  BackdropCache& c = cache_;
  std::vector<float> key = backdropKey(view, scene, lines_.style());
  if (!sameKey(c.key, key)) {  // a new view: drawn directly until it repeats
    c.key = std::move(key);
    c.drawn = false;
    c.pixelsState = BackdropCache::Pixels::None;
    return false;
  }
  if (!target.copyable) return false;
  if (!c.drawn) {
    if (!c.color.image) {
      c.color = createImage(device_, extent_, colorFormat_,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                            kColor);
      c.depth = createImage(device_, extent_, kDepthFormat,
                            VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                            kDepth);
    }
    toAttachment(commands, c.color.image, kColor);
    // WAR: frames still in flight may test against (and the splat sample) the depth of the
    // previous view.
    imageBarrier(commands, c.depth.image, kDepth, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 kDepthStages | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, kDepthStages,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    beginRendering(commands, c.color.view, c.depth.view, extent_, false);
    backdrop_.recordDraw(commands, view, scene, lines_.style());
    cmdEndRendering_(commands);
    // RAW: the copies into each frame read what the pass wrote.
    imageBarrier(commands, c.color.image, kColor, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    // RAW: every frame of this view tests against (and the splat samples) this depth,
    // read-only, in place.
    imageBarrier(commands, c.depth.image, kDepth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, kDepthStages,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | kDepthStages,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
    c.drawn = true;
  }
  if (target.hostColor && writeBackdropFromHost(commands, frame, target)) {
    backdropByHost_ = true;
    return true;
  }
  discardInto(commands, target.color, kColor, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
              VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  copyImage(commands, c.color.image, target.color, kColor, extent_);
  // RAW: the lines' pass loads the colour.
  imageBarrier(commands, target.color, kColor, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
               VK_ACCESS_TRANSFER_WRITE_BIT, kColorStage,
               VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
  return true;
}

// On a CPU device the copy into each frame is a memcpy on the device's one queue thread
// while the other cores wait; the host does it sooner, while the device still works on the
// previous frame. The cached colour is read back once (this frame), then written by the host
// from the next frame in this slot on, when the read-back has surely finished. Not under
// the splat, whose long dispatches keep every core busy: there it does not pay.
bool FrameRenderer::writeBackdropFromHost(VkCommandBuffer commands, uint32_t frame,
                                          const FrameTarget& target) {
  if (lines_.mode() == LineMode::Splat) return false;
  BackdropCache& c = cache_;
  using Pixels = BackdropCache::Pixels;
  if (c.pixelsState == Pixels::Recorded && frame == c.pixelsFrame) c.pixelsState = Pixels::Ready;
  const size_t bytes = size_t(extent_.width) * extent_.height * 4;
  if (c.pixelsState == Pixels::None) {
    if (!c.pixels.buffer()) c.pixels = ReadbackBuffer(device_, bytes);
    // WAW: a read-back of an earlier view may still be running.
    memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    c.pixels.recordCopy(commands, c.color.image, extent_);
    c.pixelsState = Pixels::Recorded;
    c.pixelsFrame = frame;
    return false;
  }
  if (c.pixelsState != Pixels::Ready) return false;
  std::memcpy(target.hostColor, c.pixels.read(), bytes);
  // The submission makes the host's writes visible to the device; the image keeps them into
  // the lines' pass, which loads the colour.
  imageBarrier(commands, target.color, kColor, target.finalLayout,
               VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_HOST_BIT,
               VK_ACCESS_HOST_WRITE_BIT, kColorStage,
               VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
  return true;
}

void FrameRenderer::record(VkCommandBuffer commands, uint32_t frame,
                           const GpuSimulation& simulation, const FrameTarget& target,
                           const OrbitCamera& camera,
                           const std::function<void(VkCommandBuffer)>& overlay) {
  resize(target.extent);
  const View view{camera.viewProj(float(target.extent.width) / float(target.extent.height)),
                  target.extent, camera.eye()};
  backdropByHost_ = false;
  backdropReused_ = copyBackdrop(commands, frame, target, view, simulation.scene());
  // A reused backdrop's depth is the cache's own (read-only: the lines do not write depth);
  // copying it would cost a frame more than the colour does on a CPU device.
  const VkImageView depth = backdropReused_ ? cache_.depth.view.get() : target.depthView;
  if (!backdropReused_) {
    toAttachment(commands, target.color, kColor);
    toAttachment(commands, target.depth, kDepth);
    beginRendering(commands, target.colorView, target.depthView, target.extent, false);
    backdrop_.recordDraw(commands, view, simulation.scene(), lines_.style());
    cmdEndRendering_(commands);
    // RAW: the lines' pass loads the colour; the splat and the depth test read the depth.
    imageBarrier(commands, target.color, kColor, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, kColorStage,
                 VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    imageBarrier(commands, target.depth, kDepth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, kDepthStages,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | kDepthStages,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
  }
  lines_.recordPrepare(commands, frame, simulation, view, depth);
  beginRendering(commands, target.colorView, depth, target.extent, true);
  lines_.recordDraw(commands, frame, simulation, view);
  cmdEndRendering_(commands);
  if (overlay) overlay(commands);
  // RAW: presentation, the read-back copy or the host reads what the frame wrote.
  const bool toTransfer = target.finalLayout == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  imageBarrier(commands, target.color, kColor, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
               target.finalLayout, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
               VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
               toTransfer ? VK_PIPELINE_STAGE_TRANSFER_BIT : VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT,
               toTransfer ? VK_ACCESS_TRANSFER_READ_BIT : 0);
}

std::vector<uint8_t> renderOffscreen(const Device& device, FrameRenderer& renderer,
                                     const GpuSimulation& simulation, const OffscreenTarget& target,
                                     const OrbitCamera& camera) {
  device.submitNow([&](VkCommandBuffer commands) {
    renderer.record(commands, 0, simulation, target.target(), camera);
    target.recordReadback(commands);
  });
  return target.pixels();
}

Scene drawnScene(Scene scene) {
  if (scene.flow) scene.flow->solver = FlowSolver::Explicit;
  return scene;
}

State drawnState(const State& state) {
  State s = state;
  s.pressure.clear();
  return s;
}

void renderFrames(Device& device, const Scene& scene, const FrameRun& run,
                  const std::function<void(uint32_t, const std::vector<uint8_t>&)>& sink) {
  std::optional<CpuSimulation> cpu;
  if (run.cpu) cpu.emplace(scene, run.cpu->threads, run.cpu->kernel);
  GpuSimulation drawn(device, cpu ? drawnScene(scene) : scene);
  Simulation& simulation = cpu ? static_cast<Simulation&>(*cpu) : drawn;
  FrameRenderer renderer(device, OffscreenTarget::kColorFormat, run.style);
  renderer.setLineMode(run.lines);
  renderer.setSettings(run.look);
  const OffscreenTarget target(device, run.size);
  OrbitCamera camera;
  if (run.start) simulation.setState(*run.start);
  std::optional<SeriesWriter> series;
  if (!run.series.empty()) {
    series.emplace(run.series, run.seriesEvery, run.start ? run.start->step : 0,
                   run.start.has_value());
    series->sampleIfDue(simulation);
  }
  const auto advance = [&](uint64_t steps) {
    series ? series->advance(simulation, steps) : simulation.advance(steps);
  };
  advance(scene.stepsIn(run.warmup));
  const double stepsPerFrame = 1.0 / (run.fps * double(scene.h()));
  common::StepAccumulator owed;
  for (uint32_t frame = 0; frame < run.frames; ++frame) {
    if (frame > 0) advance(owed.take(stepsPerFrame));
    if (cpu) drawn.setState(drawnState(cpu->view()));
    camera.yaw = 0.6f + 0.15f * float(frame / run.fps);  // a slow orbit
    sink(frame, renderOffscreen(device, renderer, drawn, target, camera));
  }
}

}  // namespace lava::host
