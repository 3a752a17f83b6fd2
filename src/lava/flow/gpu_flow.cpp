// The flow on the GPU: flow.comp's buffers and passes (docs/model.md, "The flow on the GPU").
#include "gpu_flow.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <thread>

#include "lava/error.h"
#include "sim/reference.h"
#include "sim/scene_params.h"
#include "vulkan/shaders.h"

namespace lava::detail {
namespace {

constexpr VkDeviceSize kParticleBytes = sizeof(Particle);

bool steppedOnHost(const Scene& scene) {
  return scene.flow->solver == FlowSolver::Implicit;
}

// flow.comp's grid: each bucket's count and start, the sorted slots, each run's count and
// start, each block's count and start (shared.h, kFlowGridBinding).
VkDeviceSize gridBytes(uint64_t buckets, uint64_t slots) {
  const uint64_t runs = buckets / gpu::kFlowRun;
  return (2 * buckets + 1 + slots + 2 * runs + 2 * (runs / gpu::kFlowBlock)) * sizeof(uint32_t);
}

// The scene's parameters, once its flow is known to fit the device: the sizes are checked in
// 64 bits before flowParams narrows them to the shader's 32.
gpu::FlowParams checkedParams(const DeviceContext& c, const Scene& scene) {
  uint64_t slots = 0;
  for (const FlowRange& r : flowRanges(scene)) {
    slots += r.count;
    if (r.firstSlot + r.count > UINT32_MAX)
      throw InvalidArgument("particles", "the flow's slots reach slot " +
                                             std::to_string(r.firstSlot + r.count) +
                                             ", past the 2^32 its shader addresses");
  }
  const uint64_t buckets = flowBuckets(slots);
  const uint64_t binding = std::max(slots * sizeof(gpu::FlowNext), gridBytes(buckets, slots));
  const uint64_t groups = std::max(slots, buckets) / gpu::kWorkgroupSize + 1;
  const uint64_t range = std::min<uint64_t>(c.limits.maxStorageBufferRange, c.maxAllocation);
  if (binding > range || groups > c.limits.maxComputeWorkGroupCount[0])
    throw InvalidArgument("particles", "the flow's " + std::to_string(slots) + " slots need a " +
                                           std::to_string(binding >> 20) + " MiB binding and " +
                                           std::to_string(groups) + " workgroups; device '" +
                                           c.properties.deviceName + "' allows " +
                                           std::to_string(range >> 20) + " MiB and " +
                                           std::to_string(c.limits.maxComputeWorkGroupCount[0]));
  return flowParams(scene);
}

constexpr VkBufferUsageFlags kCopied = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;

}  // namespace

// The implicit flow on the host: the CPU backends' stepper over a state of its own, of which
// only the flow slots are used. A stepper's bits do not depend on its threads or on when it
// was made, so this gives the CPU backends' bits.
struct GpuFlow::HostStep {
  explicit HostStep(const Scene& scene) : state(initialState(scene)) { rebuild(scene); }
  void rebuild(const Scene& scene) {
    stepper.reset();
    reference = std::make_unique<Reference>(scene);
    stepper = std::make_unique<FlowStepper>(*reference,
                                            std::max(1u, std::thread::hardware_concurrency()));
  }
  State state;
  std::unique_ptr<Reference> reference;
  std::unique_ptr<FlowStepper> stepper;
};

GpuFlow::GpuFlow(DeviceContext& c, const Scene& scene)
    : c_(c),
      params_(checkedParams(c, scene)),
      ranges_(flowRanges(scene)),
      slots_(params_.sizes.y),
      buckets_(params_.sizes.x),
      particles_(c, VkDeviceSize{slots_} * kParticleBytes, kCopied, MemoryUse::Device),
      heat_(c, VkDeviceSize{slots_} * sizeof(gpu::FlowHeat), kCopied, MemoryUse::Device),
      upload_(c, VkDeviceSize{slots_} * (kParticleBytes + sizeof(gpu::FlowHeat)),
              VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload),
      readback_(c, VkDeviceSize{slots_} * sizeof(gpu::FlowHeat), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                MemoryUse::Readback) {
  if (steppedOnHost(scene)) {
    host_ = std::make_unique<HostStep>(scene);
    return;
  }
  next_ = Buffer(c, VkDeviceSize{slots_} * sizeof(gpu::FlowNext),
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device);
  scratch_ = Buffer(c, VkDeviceSize{slots_} * sizeof(gpu::FlowScratch),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device);
  grid_ = Buffer(c, gridBytes(buckets_, slots_),
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                 MemoryUse::Device);
  setLayout_ =
      createSetLayout(c,
                      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                       VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                      VK_SHADER_STAGE_COMPUTE_BIT);
  layout_ =
      createPipelineLayout(c, setLayout_, VK_SHADER_STAGE_COMPUTE_BIT, sizeof(gpu::FlowStepParams));
  pipeline(scene);
}

GpuFlow::~GpuFlow() = default;

void GpuFlow::setScene(const Scene& scene) {
  params_ = flowParams(scene);
  if (host_)
    host_->rebuild(scene);
  else
    pipeline(scene);
}

VkPipeline GpuFlow::pipeline(const Scene& scene) {
  Constants constants = stepConstants(scene);
  constants.resize(gpu::kFlowEmittersConstant + 1, 0u);
  constants[gpu::kFlowEmittersConstant] = UINT32_MAX;  // the flow's key among step.comp's
  auto it = pipelines_.find(constants);
  if (it == pipelines_.end()) {
    const Spirv shader = withFloatControls(
        c_, LAVA_SPIRV(spirv::kFlowCompSpv), LAVA_SPIRV(spirv::kFlowSignedZeroSpv),
        LAVA_SPIRV(spirv::kFlowRteSpv), LAVA_SPIRV(spirv::kFlowPlainSpv));
    it = pipelines_.emplace(constants, createComputePipeline(c_, layout_, shader, constants)).first;
  }
  return it->second;
}

GpuSimulation::FlowBuffers GpuFlow::buffers() const {
  return {particles_.get(), heat_.get(), slots_};
}

void GpuFlow::recordInit(VkCommandBuffer commands, VkBuffer unborn, VkDeviceSize block) const {
  std::vector<VkBufferCopy> regions;
  const VkDeviceSize bytes = VkDeviceSize{slots_} * kParticleBytes;
  for (VkDeviceSize at = 0; at < bytes; at += block)
    regions.push_back({0, at, std::min(block, bytes - at)});
  c_.vk.CmdCopyBuffer(commands, unborn, particles_.get(), uint32_t(regions.size()), regions.data());
  c_.vk.CmdFillBuffer(commands, heat_.get(), 0, VK_WHOLE_SIZE, 0);
  if (!host_) c_.vk.CmdFillBuffer(commands, grid_.get(), 0, VK_WHOLE_SIZE, 0);
}

void GpuFlow::record(VkCommandBuffer commands, const Scene& scene, const SlotBindings& slot,
                     uint32_t steps, const std::vector<ParticleChunk>& chunks) {
  if (host_) {
    recordHost(commands, slot, steps);
    return copyToChunks(commands, chunks);
  }
  // RAW/WAR: an upload or an earlier pass wrote, or a copy into the chunks or a draw read,
  // the flow's buffers.
  const auto barrier = [&] { beforeCompute(c_, commands); };
  barrier();
  c_.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline(scene));
  Descriptors()
      .buffer(gpu::kFlowParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, particles_.get())
      .buffer(gpu::kScheduleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, slot.schedule)
      .buffer(gpu::kFlowHeatBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, heat_.get())
      .buffer(gpu::kSceneBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, slot.sceneParams, 0,
              sizeof(gpu::SceneParams))
      .buffer(gpu::kFlowParamsBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, slot.flowParams, 0,
              sizeof(gpu::FlowParams))
      .buffer(gpu::kFlowNextBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, next_.get())
      .buffer(gpu::kFlowScratchBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, scratch_.get())
      .buffer(gpu::kFlowGridBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, grid_.get())
      .bind(c_, commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, setLayout_, *slot.sets);
  const uint32_t perSlot = groupCount(slots_, gpu::kWorkgroupSize);
  uint32_t groups[gpu::kFlowPasses];  // workgroups per pass
  std::fill_n(groups, gpu::kFlowPasses, perSlot);
  groups[gpu::kFlowScan] = 1;
  groups[gpu::kFlowBlockStarts] =
      groupCount(buckets_ / (gpu::kFlowRun * gpu::kFlowBlock), gpu::kWorkgroupSize);
  groups[gpu::kFlowStarts] = groupCount(buckets_ / gpu::kFlowRun, gpu::kWorkgroupSize);
  groups[gpu::kFlowOrder] = groupCount(buckets_, gpu::kWorkgroupSize);
  gpu::FlowStepParams params{};
  params.run.z = slot.entries;
  for (uint32_t s = 0; s < steps; ++s) {
    params.run.x = s;
    for (uint32_t pass = 0; pass < gpu::kFlowPasses; ++pass) {
      if (s > 0 || pass > 0) barrier();
      params.run.y = pass;
      c_.vk.CmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                             &params);
      c_.vk.CmdDispatch(commands, groups[pass], 1, 1);
    }
  }
  copyToChunks(commands, chunks);
}

void GpuFlow::copyToChunks(VkCommandBuffer commands,
                           const std::vector<ParticleChunk>& chunks) const {
  // RAW, and WAW/WAR on the chunks: the copy reads the flow's last results (flow.comp's or
  // the host's copy) and writes over what step.comp wrote and draws read.
  memoryBarrier(c_, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
  std::vector<VkBufferCopy> regions;
  for (const ParticleChunk& chunk : chunks) {
    regions.clear();
    for (const FlowRange& r : ranges_) {
      const uint64_t first = std::max(r.firstSlot, chunk.first);
      const uint64_t end = std::min(r.firstSlot + r.count, chunk.first + chunk.count);
      if (first < end)
        regions.push_back({(r.firstIndex + first - r.firstSlot) * kParticleBytes,
                           (first - chunk.first) * kParticleBytes, (end - first) * kParticleBytes});
    }
    if (!regions.empty())
      c_.vk.CmdCopyBuffer(commands, particles_.get(), chunk.buffer, uint32_t(regions.size()),
                          regions.data());
  }
  // RAW: steps, draws and read-backs read the particles copied here.
  memoryBarrier(c_, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                    VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                    VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}

// Writes the flow slots' particles, temperatures and crust flags of `state` into the mapped
// `staging`, by flow index: the particles, then the heat.
void GpuFlow::stage(const Buffer& staging, const State& state) const {
  auto* particles = static_cast<Particle*>(staging.mapped());
  auto* heat = reinterpret_cast<gpu::FlowHeat*>(particles + slots_);
  for (const FlowRange& r : ranges_)
    for (uint64_t i = 0; i < r.count; ++i) {
      const uint64_t slot = r.firstSlot + i;
      particles[r.firstIndex + i] = state.particles[slot];
      heat[r.firstIndex + i] = {state.temperature[slot], uint32_t(state.crust[slot])};
    }
  staging.flush();
}

void GpuFlow::copyStaged(VkCommandBuffer commands, const Buffer& staging) const {
  const VkDeviceSize particleBytes = VkDeviceSize{slots_} * kParticleBytes;
  const VkBufferCopy toParticles{0, 0, particleBytes};
  const VkBufferCopy toHeat{particleBytes, 0, VkDeviceSize{slots_} * sizeof(gpu::FlowHeat)};
  c_.vk.CmdCopyBuffer(commands, staging.get(), particles_.get(), 1, &toParticles);
  c_.vk.CmdCopyBuffer(commands, staging.get(), heat_.get(), 1, &toHeat);
}

void GpuFlow::recordHost(VkCommandBuffer commands, const SlotBindings& slot, uint32_t steps) {
  State& state = host_->state;
  for (uint32_t s = 0; s < steps; ++s) {
    host_->stepper->births(state, *slot.births, s);
    host_->stepper->step(state);
  }
  Buffer& staging = *slot.staging;
  if (!staging.get())
    staging = Buffer(c_, upload_.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
  stage(staging, state);
  // WAW/WAR: earlier copies wrote, and draws and copies read, what is overwritten here.
  memoryBarrier(c_, commands,
                VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                    VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_TRANSFER_WRITE_BIT);
  copyStaged(commands, staging);
}

void GpuFlow::upload(const State& state) {
  if (host_)
    for (const FlowRange& r : ranges_)
      for (uint64_t slot = r.firstSlot; slot < r.firstSlot + r.count; ++slot) {
        host_->state.particles[slot] = state.particles[slot];
        host_->state.temperature[slot] = state.temperature[slot];
        host_->state.crust[slot] = state.crust[slot];
        host_->state.pressure[slot] = state.pressure[slot];
      }
  stage(upload_, state);
  c_.submitNow([&](VkCommandBuffer commands) {
    // WAW/WAR: earlier passes wrote and read what is overwritten here.
    memoryBarrier(c_, commands,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    copyStaged(commands, upload_);
    if (!host_) c_.vk.CmdFillBuffer(commands, grid_.get(), 0, VK_WHOLE_SIZE, 0);
  });
}

void GpuFlow::download(State& state) {
  if (host_) {  // the host's own, as of the last recorded step
    state.pressure.assign(state.particles.size(), 0.0f);
    for (const FlowRange& r : ranges_)
      for (uint64_t slot = r.firstSlot; slot < r.firstSlot + r.count; ++slot) {
        state.temperature[slot] = host_->state.temperature[slot];
        state.crust[slot] = host_->state.crust[slot];
        state.pressure[slot] = host_->state.pressure[slot];
      }
    return;
  }
  c_.submitNow([&](VkCommandBuffer commands) {
    // RAW: flow.comp wrote the heat this copy reads; the host reads what it writes.
    memoryBarrier(c_, commands,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    const VkBufferCopy region{0, 0, VkDeviceSize{slots_} * sizeof(gpu::FlowHeat)};
    c_.vk.CmdCopyBuffer(commands, heat_.get(), readback_.get(), 1, &region);
    memoryBarrier(c_, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  });
  readback_.invalidate();
  const auto* heat = static_cast<const gpu::FlowHeat*>(readback_.mapped());
  for (const FlowRange& r : ranges_)
    for (uint64_t i = 0; i < r.count; ++i) {
      state.temperature[r.firstSlot + i] = heat[r.firstIndex + i].temperature;
      state.crust[r.firstSlot + i] = uint8_t(heat[r.firstIndex + i].crust);
    }
}

}  // namespace lava::detail
