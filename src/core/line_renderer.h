// Draws the scene into a target it is given: the ground and crater, then one line per
// particle pulled from the simulation's particle buffer (no copy). The swapchain and the
// offscreen image are both just targets of renderPass().
//
// The ground and crater are the same while the camera, the crater and the size are: from
// the second frame that repeats them, they are drawn once into images of the renderer's
// own and copied into each target (two memcpys on a CPU device instead of shading every
// pixel again), when the target's images accept copies.
#pragma once
#include <functional>
#include <vector>

#include "camera.h"
#include "context.h"
#include "gpu_simulator.h"
#include "offscreen_target.h"
#include "scene.h"
#include "splat_pass.h"

namespace lava {

// How the lines reach the target: the graphics pipeline (the reference) or splat.comp.
enum class LineMode { Pipeline, Splat };

class LineRenderer {
 public:
  static constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

  // finalLayout: the color attachment's layout after the pass (transfer source offscreen,
  // present source for a swapchain).
  LineRenderer(Context& context, const GpuSimulator& simulator, VkFormat colorFormat,
               VkImageLayout finalLayout);

  VkRenderPass renderPass() const { return renderPass_; }
  // Points the line pipeline at `simulator`'s particle buffer (after a restart).
  void bind(const GpuSimulator& simulator);
  void setMode(LineMode mode) { mode_ = mode; }
  LineMode mode() const { return mode_; }
  // Records the barrier after step.comp, then the render pass into `target`; `overlay`
  // (e.g. the UI) records into the same pass after the lines. A target's color image must
  // not be read between two records of one command buffer (the cache is one image).
  void record(VkCommandBuffer commands, const RenderTarget& target, const OrbitCamera& camera,
              const Scene& scene, const std::function<void(VkCommandBuffer)>& overlay = {});
  // Whether the last record() copied the cached ground instead of drawing it (for tests).
  bool groundWasCopied() const { return groundCopied_; }

 private:
  // The cached ground: images, what they show, and whether they hold it yet.
  struct GroundCache {
    ImageWithMemory color, depth;
    UniqueFramebuffer framebuffer;
    VkExtent2D extent{0, 0};
    glm::mat4 viewProj{0.0f};
    glm::vec4 crater{0.0f};
    bool drawn = false;
  };
  void drawGround(VkCommandBuffer commands, const gpu::DrawParams& params);
  // Whether this view's ground comes from the cache; draws the cache first if needed.
  bool prepareCache(VkCommandBuffer commands, const RenderTarget& target,
                    const gpu::DrawParams& params);

  Context& context_;
  VkFormat colorFormat_;
  bool cacheable_;               // the color and depth formats accept copies
  UniqueRenderPass renderPass_;  // PassKind::Clear
  UniqueRenderPass loadPass_;
  UniqueRenderPass backgroundPass_;
  GroundCache cache_;
  bool groundCopied_ = false;
  UniqueDescriptorSetLayout setLayout_;
  UniquePipelineLayout pipelineLayout_;
  UniquePipeline groundPipeline_;
  UniquePipeline linePipeline_;
  UniqueDescriptorPool descriptorPool_;
  std::vector<ParticleChunk> chunks_;
  SplatPass splat_;
  LineMode mode_ = LineMode::Pipeline;
};

// Below this many particles the graphics line pipeline is faster than splatting on lavapipe
// (docs/benchmarks.md): the renderer to use when the user did not say.
constexpr uint32_t kSplatFrom = 16384;
inline LineMode defaultLineMode(uint32_t particles) {
  return particles >= kSplatFrom ? LineMode::Splat : LineMode::Pipeline;
}

// Parses "lines" or "splat" for the flag named by `source` (UsageError otherwise).
LineMode parseLineMode(const std::string& source, const std::string& text);

}  // namespace lava
