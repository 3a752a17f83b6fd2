// Drawing a GpuSimulation into the host's images: each alive particle is the line from x to
// x + lineScale * v, read straight from the buffers the compute shader wrote. Pipelines are
// built for the host's formats (dynamic rendering) or for its render pass and subpass.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>

#include "device.h"
#include "export.h"
#include "math.h"
#include "scene.h"

namespace lava {

class GpuSimulation;

// Where Lava draws: the host's attachments, a color format (UNORM: the lava look blends in
// [0, 1]) and a depth format or VK_FORMAT_UNDEFINED (none), in dynamic rendering; or, with
// `renderPass`, subpass `subpass` of that render pass or of any pass compatible with it, as
// Dear ImGui's backend does. The subpass has one color attachment, single sampled, and a
// depth attachment exactly when `depth` is not UNDEFINED (Lava only tests against it: its
// layout may be DEPTH_STENCIL_READ_ONLY_OPTIMAL; the Backdrop writes it).
// Lava's barriers are recorded outside the pass, so the subpass needs no dependency for
// Lava's own work; the host's dependencies cover its attachments as for any draw.
// Lifetime: `renderPass` is read only during the LineRenderer or Backdrop constructor, which
// builds every pipeline it will use for it; Lava keeps no handle of it, so the host may
// destroy it right after and draw in a compatible pass it remakes at every resize.
struct RenderFormats {
  VkFormat color = VK_FORMAT_R8G8B8A8_UNORM;
  VkFormat depth = VK_FORMAT_D32_SFLOAT;
  VkRenderPass renderPass = VK_NULL_HANDLE;  // none: dynamic rendering
  uint32_t subpass = 0;
};

// What is drawn from where, into a target of which size.
struct View {
  // World (m) to Vulkan clip space (y down, depth 0..1). The flow's molten surface reads the
  // camera's axes and focal lengths from its rows: a rigid view under a symmetric, unskewed
  // perspective (as OrbitCamera's); an off-centre or jittered projection misplaces its
  // normals and depth.
  Mat4 viewProj;
  VkExtent2D extent{0, 0};  // the target, in pixels: recordDraw sets viewport and scissor to it
  Vec3 eye;                 // the camera's position (m): walls are drawn from the front only
};

// How lines reach the target: the graphics pipeline (the reference), or splat, a compute
// pass that walks each line in screen space and adds it into a buffer the size of the
// target (faster on CPU devices for many particles).
enum class LineMode { Lines, Splat };

// How lines look. Lava: molten rock, hot and yellow when fresh, orange when slow, red when
// fast, cooling to a dark crust that stays visible (a line at rest is drawn at least
// 1.25 px long), its energy tone mapped as it is added (the target holds 1 - exp(-energy):
// dense lava turns yellow instead of clipping to white) and glowing into its surroundings;
// over a Backdrop drawn in the same look. Plain: the lab handout's colours, added and clipped.
enum class LookStyle { Lava, Plain };

struct LookSettings {
  float exposure = 1.0f;   // scales the lava's energy before the tone map, (0, 16]
  float bloom = 1.0f;      // strength of the glow around bright lava, [0, 4] (0: none)
  float threshold = 0.1f;  // energy per pixel (of a 16x16 cell) below which nothing glows
};

// Thread safety: one thread at a time per object, recordDraw() included (it is const but
// writes the frame slot's descriptor sets where the device has no push descriptors);
// distinct objects on one Device on distinct threads (see Device).
// Nothing in the class submits or waits: its set-up (an image's first layout, emptied
// lists) is recorded by the next recordPrepare(). Destroy it once the host's last
// submission that used it has finished.
class LAVA_API LineRenderer {
 public:
  LineRenderer(Device& device, const RenderFormats& formats);
  ~LineRenderer();
  LineRenderer(const LineRenderer&) = delete;
  LineRenderer& operator=(const LineRenderer&) = delete;

  void setMode(LineMode mode);
  LineMode mode() const;
  // The lava look (the default) or the plain look; the look's settings.
  void setStyle(LookStyle style);
  LookStyle style() const;
  void setSettings(const LookSettings& settings);
  const LookSettings& settings() const;
  // For a host that gives recordPrepare() no depth view (a pass with colour only): on,
  // recordPrepare() draws the depth of the scene's solids (the ground, the colliders, a
  // crater's scenery: what a Backdrop draws) into an image of Lava's own per frame slot, in
  // a render pass of its own outside the host's, and the splat (LineMode::Splat) tests
  // against it, so that solids hide the lava behind them; the lines of LineMode::Lines and
  // the flow's surface do not. Off by default; a depth view given to recordPrepare() is used instead.
  // Costs a depth image per frame slot and a depth-only pass at the target's size a frame
  // (docs/benchmarks.md).
  void setSceneDepth(bool on);
  bool sceneDepth() const;
  // Not a recording call: sizes the splat's and the glow's per-frame buffers for targets
  // of `extent` (allocates, and in dynamic rendering builds the pipelines that read the
  // splat's sums and the glow's cells on the first call or when either outgrows the device's
  // texel views, which the spec lets hold as few as 65,536 texels; for a render pass the
  // constructor built them all; call it before recording for a new size,
  // when no frame using the old buffers is pending), for each frame slot in use (a slot's
  // first recordPrepare() adds its own; for a simulation with a flow, the molten surface's
  // buffers too, at half the extent each way). recordPrepare() requires view.extent == the
  // last setExtent() (with the lines' graphics pipeline and no glow, only for a flow).
  void setExtent(VkExtent2D extent);

  // Outside rendering, after the simulation's recordSimulate():
  // a barrier from the particle writes (COMPUTE_SHADER / SHADER_WRITE) to this renderer's
  // reads (VERTEX_SHADER and COMPUTE_SHADER / SHADER_READ); in splat mode, frame slot
  // `frame`'s splat pass (a fill, then compute); in the lava look, its glow passes (fills,
  // then compute); for a simulation with a flow, its molten surface's passes (fills, then
  // compute: docs/flow.md, "On screen"); their results made visible to the draw (DRAW_INDIRECT, VERTEX_SHADER,
  // FRAGMENT_SHADER reads). `depth` (optional; the recorded commands use it, so it must
  // live until they have finished): a view of the scene's depth (the format
  // given at construction; the image made with VK_IMAGE_USAGE_SAMPLED_BIT besides
  // DEPTH_STENCIL_ATTACHMENT) that the splat tests against as the pipeline's depth test
  // does. It must be complete when this is recorded: written in an earlier rendering pass
  // (the Backdrop's), then in VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, its writes
  // made visible to COMPUTE_SHADER reads by the host's barrier (or its pass's dependency);
  // docs/library.md, "The frame recipe". Records only: no submission or wait. The first call
  // (and the first after setExtent()) also records the renderer's set-up, and the
  // simulation's recordInit() when still due.
  // It starts slot `frame`'s frame: the host's previous submission that used `frame` must
  // have finished. On a device without VK_KHR_push_descriptor this and recordDraw() write
  // the slot's descriptor sets (allocated from Lava's own pool by the slot's first frames,
  // then reused), so their command buffer cannot be submitted again after the slot's next
  // recordPrepare().
  void recordPrepare(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                     const View& view, VkImageView depth = VK_NULL_HANDLE);
  // Inside the host's dynamic rendering scope (vkCmdBeginRendering) with the formats given
  // at construction, or in the render pass's subpass given (a UNORM colour target: the lava
  // look blends src (1 - dst) + dst), the colour attachment in COLOR_ATTACHMENT_OPTIMAL:
  // draws the flow's molten surface (opaque), then the lines, both depth-tested against the
  // depth attachment (not written; it may be in DEPTH_STENCIL_READ_ONLY_OPTIMAL, as the view
  // given to recordPrepare() is), the lines behind the surface left out, then the glow. Sets
  // viewport, scissor, pipeline and push constants. Records only.
  void recordDraw(VkCommandBuffer commands, uint32_t frame, const GpuSimulation& simulation,
                  const View& view) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The ground plane (a 1 m grid, 24 m across) and the scene's colliders as solids (a plane as
// an 8 m square seen from its front); a scene without colliders whose emitter 0 is a disc
// gets a crater of scenery under it. Opaque; writes depth.
// Thread safety: recordDraw() from any thread into distinct command buffers (it reads only
// what the constructor made); construction and destruction as its Device's. Nothing in the
// class submits or waits; destroy it once the host's last submission that used it has
// finished.
class LAVA_API Backdrop {
 public:
  Backdrop(Device& device, const RenderFormats& formats);
  ~Backdrop();
  Backdrop(const Backdrop&) = delete;
  Backdrop& operator=(const Backdrop&) = delete;

  // Inside dynamic rendering with the formats given at construction (or the render pass's
  // subpass given), colour in COLOR_ATTACHMENT_OPTIMAL and depth writable
  // (DEPTH_ATTACHMENT_OPTIMAL or DEPTH_STENCIL_ATTACHMENT_OPTIMAL): the solids, opaque,
  // writing depth, and in the lava look a sky where the depth is still the far plane (the
  // depth cleared to 1; without a depth format the sky is drawn first). Records only.
  void recordDraw(VkCommandBuffer commands, const View& view, const Scene& scene,
                  LookStyle style = LookStyle::Lava) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Below this many particles the graphics pipeline draws faster than the splat on a CPU
// device (lavapipe); from it on, the splat.
constexpr uint64_t kSplatFrom = 16384;

}  // namespace lava
