#include "frame_renderer.h"

#include <cstring>

namespace lava::host {
namespace {

constexpr VkImageAspectFlags kColor = VK_IMAGE_ASPECT_COLOR_BIT;
constexpr VkImageAspectFlags kDepth = VK_IMAGE_ASPECT_DEPTH_BIT;
constexpr VkPipelineStageFlags kDepthStages =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
constexpr VkPipelineStageFlags kColorStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;

// What shapes the ground and crater: they are redrawn when any of it changes.
std::vector<float> craterOf(const Scene& scene) {
  const Emitter& e = scene.emitters.at(0);
  std::vector<float> key{e.position.x, e.position.y, e.position.z, e.radius};
  for (const Collider& c : scene.colliders)
    if (c.type == ColliderType::Cone)
      key.insert(key.end(),
                 {c.position.x, c.position.y, c.position.z, c.baseRadius, c.topRadius, c.height});
  return key;
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

// RAW: the attachment writes (or the copy) before, the stage named after.
void fromTransferToAttachment(VkCommandBuffer commands, VkImage image, VkImageAspectFlags aspect) {
  const bool color = aspect == kColor;
  imageBarrier(
      commands, image, aspect, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
      color ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
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

FrameRenderer::FrameRenderer(Device& device, VkFormat colorFormat, uint32_t framesInFlight)
    : device_(device),
      colorFormat_(colorFormat),
      backdrop_(device, {colorFormat, kDepthFormat}),
      lines_(device, {colorFormat, kDepthFormat}, framesInFlight),
      cmdBeginRendering_(deviceFunction<PFN_vkCmdBeginRendering>(device, "vkCmdBeginRendering",
                                                                 "vkCmdBeginRenderingKHR")),
      cmdEndRendering_(deviceFunction<PFN_vkCmdEndRendering>(device, "vkCmdEndRendering",
                                                             "vkCmdEndRenderingKHR")) {}

void FrameRenderer::beginRendering(VkCommandBuffer commands, VkImageView color, VkImageView depth,
                                   VkExtent2D extent, bool load) const {
  VkRenderingAttachmentInfo colorAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  colorAttachment.imageView = color;
  colorAttachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  colorAttachment.loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
  colorAttachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  colorAttachment.clearValue.color = {{0.012f, 0.010f, 0.018f, 1.0f}};
  VkRenderingAttachmentInfo depthAttachment = colorAttachment;
  depthAttachment.imageView = depth;
  depthAttachment.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depthAttachment.clearValue.depthStencil = {1.0f, 0};
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, extent};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &colorAttachment;
  info.pDepthAttachment = &depthAttachment;
  cmdBeginRendering_(commands, &info);
}

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  device_.waitIdle();  // frames in flight may still read the per-size resources
  lines_.setExtent(extent);
  cache_ = {};
  cache_.extent = extent;
  extent_ = extent;
}

bool FrameRenderer::prepareGround(VkCommandBuffer commands, const FrameTarget& target,
                                  const View& view, const Scene& scene) {
  GroundCache& c = cache_;
  std::vector<float> crater = craterOf(scene);
  const bool same =
      std::memcmp(c.viewProj.m, view.viewProj.m, sizeof(c.viewProj.m)) == 0 && c.crater == crater;
  if (!same) {  // a new view: drawn directly until it repeats
    c.viewProj = view.viewProj;
    c.crater = std::move(crater);
    c.drawn = false;
    return false;
  }
  if (!target.copyable) return false;
  if (!c.drawn) {
    if (!c.color.image) {
      c.color = createImage(device_, c.extent, colorFormat_,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                            kColor);
      c.depth = createImage(
          device_, c.extent, kDepthFormat,
          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, kDepth);
    }
    toAttachment(commands, c.color.image, kColor);
    toAttachment(commands, c.depth.image, kDepth);
    beginRendering(commands, c.color.view, c.depth.view, c.extent, false);
    backdrop_.recordDraw(commands, view, scene);
    cmdEndRendering_(commands);
    // RAW: the copies into each frame read what the pass wrote.
    imageBarrier(commands, c.color.image, kColor, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    imageBarrier(commands, c.depth.image, kDepth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kDepthStages,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    c.drawn = true;
  }
  discardInto(commands, target.color, kColor, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
              VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  discardInto(commands, target.depth, kDepth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
              VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  copyImage(commands, c.color.image, target.color, kColor, c.extent);
  copyImage(commands, c.depth.image, target.depth, kDepth, c.extent);
  fromTransferToAttachment(commands, target.color, kColor);
  fromTransferToAttachment(commands, target.depth, kDepth);
  return true;
}

void FrameRenderer::record(VkCommandBuffer commands, uint32_t frame,
                           const GpuSimulation& simulation, const FrameTarget& target,
                           const OrbitCamera& camera,
                           const std::function<void(VkCommandBuffer)>& overlay) {
  resize(target.extent);
  const View view{camera.viewProj(float(target.extent.width) / float(target.extent.height)),
                  target.extent, camera.eye()};
  lines_.recordPrepare(commands, frame, simulation, view);
  groundCopied_ = prepareGround(commands, target, view, simulation.scene());
  if (!groundCopied_) {
    toAttachment(commands, target.color, kColor);
    toAttachment(commands, target.depth, kDepth);
  }
  beginRendering(commands, target.colorView, target.depthView, target.extent, groundCopied_);
  if (!groundCopied_) backdrop_.recordDraw(commands, view, simulation.scene());
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

std::vector<uint8_t> renderOffscreen(const Submitter& submitter, FrameRenderer& renderer,
                                     const GpuSimulation& simulation, const OffscreenTarget& target,
                                     const OrbitCamera& camera) {
  submitter.submitNow([&](VkCommandBuffer commands) {
    renderer.record(commands, 0, simulation, target.target(), camera);
    target.recordReadback(commands);
  });
  return target.pixels();
}

}  // namespace lava::host
