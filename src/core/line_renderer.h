// Draws the scene into a framebuffer it is given: the ground and crater, then one line per
// particle pulled from the simulation's particle buffer (no copy). The swapchain and the
// offscreen image are both just targets of renderPass().
#pragma once
#include <functional>
#include <vector>

#include "camera.h"
#include "context.h"
#include "gpu_simulator.h"
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
  // Records the barrier after step.comp, then the render pass into `framebuffer`;
  // `overlay` (e.g. the UI) records into the same pass after the lines.
  void record(VkCommandBuffer commands, VkFramebuffer framebuffer, VkExtent2D extent,
              const OrbitCamera& camera, const Scene& scene,
              const std::function<void(VkCommandBuffer)>& overlay = {});

 private:
  Context& context_;
  UniqueRenderPass renderPass_;
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
