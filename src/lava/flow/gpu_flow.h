// The flow on the GPU (docs/model.md, "The flow on the GPU"): the flow's own copy of its
// particles, their temperatures and crust flags, its grid, and flow.comp's passes, for a
// GpuSimulation whose scene has flow emitters. GpuSimulation plans the births and owns the
// state's chunks; this records the flow's steps over them. The implicit flow has no shader
// yet: the host steps it with the CPU backends' code (the same bits) as the steps are
// recorded, and the recording copies its particles to the device.
#pragma once
#include <map>
#include <memory>
#include <vector>

#include "flow.h"
#include "lava/simulation.h"
#include "vulkan/buffer.h"
#include "vulkan/commands.h"
#include "vulkan/pipeline.h"

namespace lava::detail {

class GpuFlow {
 public:
  // Its buffers are one binding each, its passes one dispatch each: a flow beyond the
  // device's binding range, allocation or workgroup count is InvalidArgument ("particles").
  GpuFlow(DeviceContext& context, const Scene& scene);
  ~GpuFlow();

  // The scene's parameters (what each frame slot's uniform holds) and pipeline, made when a
  // scene is set, never while recording. Its flow emitters and capacities are the same.
  void setScene(const Scene& scene);
  const gpu::FlowParams& params() const { return params_; }

  // What one frame slot binds besides the flow's own buffers.
  struct SlotBindings {
    VkBuffer schedule;     // the births (gpu::EmitEntry), `entries` per emitter
    VkBuffer sceneParams;  // gpu::SceneParams
    VkBuffer flowParams;   // gpu::FlowParams: params() as the slot's steps were planned
    uint32_t entries;
    DescriptorArena* sets;  // without push descriptors
    // The implicit flow's: each emitter's births of each step planned (flow emitters'
    // only), and the slot's host-written copy of the particles and heat stepped on the host.
    const std::vector<std::vector<Births>>* births;
    Buffer* staging;
  };
  // Records: every flow slot unborn (copied from the first `bytes` of `unborn`, a block of
  // unborn particles), 0 K, no crust, the grid's counts 0.
  void recordInit(VkCommandBuffer commands, VkBuffer unborn, VkDeviceSize bytes) const;
  // Records `steps` steps (the slot's schedule entries 0 to steps - 1), nine passes each
  // with a barrier between them, then the flow's particles into the state's `chunks`. The
  // implicit flow: steps them on the host now, then records their copy from the slot's
  // staging (written now: its last submission must have finished) to the device.
  void record(VkCommandBuffer commands, const Scene& scene, const SlotBindings& slot,
              uint32_t steps, const std::vector<ParticleChunk>& chunks);
  // Blocking: the flow's copy from `state` (particles, temperatures, crust flags; the grid's
  // counts 0), or its temperatures and crust flags into `state` (whose columns are sized).
  void upload(const State& state);
  void download(State& state);

  GpuSimulation::FlowBuffers buffers() const;
  bool onHost() const { return host_ != nullptr; }  // the implicit flow: stepped on the host

 private:
  VkPipeline pipeline(const Scene& scene);
  // Records the copy of the flow's particles over their slots in the state's chunks.
  void copyToChunks(VkCommandBuffer commands, const std::vector<ParticleChunk>& chunks) const;
  void recordHost(VkCommandBuffer commands, const SlotBindings& slot, uint32_t steps);
  void stage(const Buffer& staging, const State& state) const;
  // Records the copy of a staged state's particles and heat to the flow's own buffers.
  void copyStaged(VkCommandBuffer commands, const Buffer& staging) const;

  DeviceContext& c_;
  gpu::FlowParams params_;
  std::vector<FlowRange> ranges_;
  uint32_t slots_, buckets_;
  Buffer particles_, heat_, next_, scratch_, grid_;
  Buffer upload_, readback_;  // upload()'s particles then heat; download()'s heat
  UniqueDescriptorSetLayout setLayout_;
  UniquePipelineLayout layout_;
  // One pipeline per set of modules a scene used (kept: a frame in flight may use it).
  std::map<Constants, UniquePipeline> pipelines_;
  struct HostStep;  // the implicit flow's: its stepper and state on the host
  std::unique_ptr<HostStep> host_;
};

}  // namespace lava::detail
