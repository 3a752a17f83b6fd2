#include "gpu_simulator.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "descriptors.h"
#include "pipeline.h"
#include "step_comp.h"
#include "vk_check.h"

namespace lava {
namespace {

constexpr VkDeviceSize kParticleBytes = sizeof(Particle);

}  // namespace

uint32_t particlesPerChunk(const Context& context) {
  const uint64_t perBinding = std::min<uint64_t>(
      {context.limits().maxStorageBufferRange / kParticleBytes,
       context.maxAllocationSize() / kParticleBytes,
       uint64_t{context.limits().maxComputeWorkGroupCount[0]} * gpu::kWorkgroupSize});
  return static_cast<uint32_t>(perBinding - perBinding % gpu::kWorkgroupSize);
}

uint64_t maxParticles(const Context& context) {
  return std::min<uint64_t>(context.deviceMemory() / kParticleBytes, 0x80000000u);
}

GpuSimulator::GpuSimulator(Context& context, const Scene& scene)
    : Simulator(scene), context_(context) {
  const uint64_t limit = maxParticles(context);
  if (scene.particles > limit)
    throw UsageError("--particles: " + std::to_string(scene.particles) + " particles need " +
                     std::to_string((scene.particles * kParticleBytes) >> 20) + " MiB; device '" +
                     context.properties().deviceName + "' allows at most " + std::to_string(limit) +
                     " (see 'lava info')");
  const uint32_t perChunk = particlesPerChunk(context);
  const VkMemoryPropertyFlags hostMemory =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  particles_.reserve((scene.particles + perChunk - 1) / perChunk);
  for (uint32_t first = 0; first < scene.particles; first += perChunk) {
    const uint32_t count = std::min(perChunk, scene.particles - first);
    particles_.emplace_back(context, VkDeviceSize{count} * kParticleBytes,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    chunks_.push_back({first, count, particles_.back().get()});
  }
  staging_ =
      Buffer(context, VkDeviceSize{chunks_.front().count} * kParticleBytes,
             VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, hostMemory);
  schedule_ = Buffer(context, kStepsPerSubmit * sizeof(gpu::EmitEntry),
                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, hostMemory);
  planned_.resize(kStepsPerSubmit + 1);

  VkDevice device = context.device();
  setLayout_ =
      createSetLayout(device,
                      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
                      VK_SHADER_STAGE_COMPUTE_BIT);
  pipelineLayout_ = createPipelineLayout(device, setLayout_, VK_SHADER_STAGE_COMPUTE_BIT,
                                         sizeof(gpu::StepParams));
  pipeline_ = createComputePipeline(device, pipelineLayout_, kStepCompSpv, sizeof(kStepCompSpv),
                                    gpu::kWorkgroupSize);

  const uint32_t chunkCount = static_cast<uint32_t>(chunks_.size());
  descriptorPool_ = createPool(device, chunkCount,
                               {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * chunkCount},
                                {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, chunkCount}});
  for (ParticleChunk& chunk : chunks_) {
    chunk.set = allocateSet(device, descriptorPool_, setLayout_);
    texelViews_.push_back(createTexelView(device, chunk.buffer, chunk.count * kParticleBytes));
    chunk.texels = texelViews_.back();
    writeTexels(device, chunk.set, gpu::kParticleTexelBinding, chunk.texels);
    writeStorage(device, chunk.set, gpu::kParticleBinding,
                 {chunk.buffer, 0, chunk.count * kParticleBytes});
    writeStorage(device, chunk.set, gpu::kScheduleBinding, {schedule_.get(), 0, VK_WHOLE_SIZE});
  }
  load(initialState(scene));
}

void GpuSimulator::load(const SimState& state) {
  clock_ = state.clock;
  for (const ParticleChunk& chunk : chunks_) {
    const VkDeviceSize bytes = chunk.count * kParticleBytes;
    std::memcpy(staging_.mapped(), state.particles.data() + chunk.first, bytes);
    context_.submitNow([&](VkCommandBuffer commands) {
      // WAW/WAR: earlier dispatches wrote, and a download read, the particles overwritten here.
      memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_TRANSFER_WRITE_BIT);
      VkBufferCopy region{0, 0, bytes};
      vkCmdCopyBuffer(commands, staging_.get(), chunk.buffer, 1, &region);
    });
  }
}

SimState GpuSimulator::state() {
  SimState out;
  out.particles.resize(scene_.particles);
  for (const ParticleChunk& chunk : chunks_) {
    const VkDeviceSize bytes = chunk.count * kParticleBytes;
    context_.submitNow([&](VkCommandBuffer commands) {
      // RAW: step.comp wrote the particles this copy reads.
      memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
      VkBufferCopy region{0, 0, bytes};
      vkCmdCopyBuffer(commands, chunk.buffer, staging_.get(), 1, &region);
      // RAW: the host reads what the copy wrote into staging.
      memoryBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    });
    std::memcpy(out.particles.data() + chunk.first, staging_.mapped(), bytes);
  }
  out.clock = clock_;
  return out;
}

void GpuSimulator::setScene(const Scene& scene) {
  if (scene.particles != scene_.particles)
    throw UsageError("--particles: the capacity of a running simulation cannot change");
  scene_ = scene;
}

void GpuSimulator::planSteps(uint32_t first, uint32_t count) {
  if (first + count > kStepsPerSubmit)
    throw std::out_of_range("planSteps: schedule has " + std::to_string(kStepsPerSubmit) +
                            " entries");
  auto* entries = static_cast<gpu::EmitEntry*>(schedule_.mapped());
  uint64_t births = 0;  // only differences within one dispatch matter
  for (uint32_t k = first; k < first + count; ++k) {
    EmitStep e = clock_.advance(scene_.rate, scene_.dt, scene_.particles);
    entries[k].ring = {e.head, e.count, static_cast<uint32_t>(e.firstSerial),
                       static_cast<uint32_t>(e.firstSerial >> 32)};
    entries[k].sums = {static_cast<uint32_t>(births), 0u, 0u, 0u};
    planned_[k] = births;
    births += e.count;
  }
  planned_[first + count] = births;
}

void GpuSimulator::recordSteps(VkCommandBuffer commands, uint32_t first, uint32_t count) const {
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  gpu::StepParams params = stepParams(scene_);
  for (uint32_t done = 0, steps = 0; done < count; done += steps) {
    // At most kStepsPerDispatch steps and fewer than 2^31 births (the shader's 32-bit sums).
    steps = 1;
    while (done + steps < count && steps < stepsPerDispatch_ &&
           planned_[first + done + steps + 1] - planned_[first + done] < (1ull << 31))
      ++steps;
    // RAW/WAW: the previous dispatch or upload wrote the particles this one reads and writes;
    // WAR: lines.vert of the last frame read them.
    memoryBarrier(commands,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                      VK_PIPELINE_STAGE_VERTEX_SHADER_BIT,
                  VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                  VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    params.run.z = first + done;
    params.run.w = steps;
    for (const ParticleChunk& chunk : chunks_) {
      params.chunk = {chunk.first, chunk.count, 0u, 0u};
      vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_, 0, 1,
                              &chunk.set, 0, nullptr);
      vkCmdPushConstants(commands, pipelineLayout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params),
                         &params);
      const uint32_t invocations =
          (chunk.count + gpu::kParticlesPerInvocation - 1) / gpu::kParticlesPerInvocation;
      vkCmdDispatch(commands, (invocations + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1, 1);
    }
  }
}

void GpuSimulator::advance(uint64_t steps) {
  while (steps > 0) {
    const uint32_t batch = static_cast<uint32_t>(std::min<uint64_t>(steps, kStepsPerSubmit));
    planSteps(0, batch);
    context_.submitNow([&](VkCommandBuffer commands) { recordSteps(commands, 0, batch); });
    steps -= batch;
  }
}

double GpuSimulator::advanceTimed(uint64_t steps) {
  const TimestampPair timer(context_);
  double seconds = 0.0;
  while (steps > 0) {
    const uint32_t batch = static_cast<uint32_t>(std::min<uint64_t>(steps, kStepsPerSubmit));
    planSteps(0, batch);
    context_.submitNow([&](VkCommandBuffer commands) {
      timer.recordStart(commands);
      recordSteps(commands, 0, batch);
      timer.recordEnd(commands);
    });
    seconds += timer.seconds();
    steps -= batch;
  }
  return seconds;
}

}  // namespace lava
