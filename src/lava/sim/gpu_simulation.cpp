// The Vulkan backend: step.comp over the particles, held in chunks of at most one binding,
// one texel view, one dispatch and one allocation each; many steps per dispatch. The host
// plans each frame's emission into that frame's slot of a host-visible schedule.
#include <algorithm>
#include <cstring>

#include "emission.h"
#include "lava/error.h"
#include "lava/simulation.h"
#include "model.h"
#include "shared.h"
#include "vulkan/buffer.h"
#include "vulkan/check.h"
#include "vulkan/commands.h"
#include "vulkan/pipeline.h"
#include "vulkan/shaders.h"
#include "vulkan/timestamps.h"

namespace lava {

using detail::Buffer;
using detail::MemoryUse;

namespace {

constexpr VkDeviceSize kParticleBytes = sizeof(Particle);
constexpr uint32_t kMaxStepsPerDispatch = 256;
constexpr uint32_t kBlockingSteps = 4096;  // steps one blocking submission runs

// One slot of the schedule: the entries of the steps planned into it, and on the host the
// births before each entry (to keep a dispatch under 2^31 births).
struct ScheduleSlot {
  VkDeviceSize offset = 0;       // in the schedule buffer
  uint32_t capacity = 0;         // entries it holds
  uint32_t planned = 0;          // entries the last update() wrote
  std::vector<uint64_t> births;  // births before entry i (capacity + 1)
};

// Push constants of one dispatch; the caller fills run.zw and chunk.
gpu::StepParams stepParams(const Scene& s) {
  const Emitter& e = s.emitters[0];
  gpu::StepParams p{};
  p.emitter = glm::vec4(e.position.x, e.position.y, e.position.z, e.radius);
  p.velocity = glm::vec4(e.velocity.x, e.velocity.y, e.velocity.z, s.h());
  p.spread = glm::vec4(e.spread.x, e.spread.y, e.spread.z, s.gravity);
  p.wind = glm::vec4(s.wind.x, s.wind.y, s.wind.z, s.drag);
  p.material = glm::vec4(s.restitution, s.friction, e.mass, 0.0f);
  p.run = glm::uvec4(s.seed, e.particles, 0u, 0u);
  return p;
}

}  // namespace

struct GpuSimulation::Impl {
  detail::DeviceContext& c;
  GpuSimulationOptions options;
  std::vector<Buffer> buffers;  // one per chunk
  std::vector<detail::UniqueBufferView> views;
  std::vector<ParticleChunk> chunks;
  Buffer upload, readback;  // one chunk's worth each, for setState() and state()
  Buffer schedule;
  std::vector<ScheduleSlot> slots;  // framesInFlight frame slots, then the blocking slot
  detail::UniqueDescriptorSetLayout setLayout;
  detail::UniquePipelineLayout pipelineLayout;
  detail::UniquePipeline pipeline;
  std::vector<EmitterClock> clocks;
  uint64_t step = 0;

  Impl(detail::DeviceContext& context, const GpuSimulationOptions& o) : c(context), options(o) {}

  uint32_t blockingSlot() const { return options.framesInFlight; }
  void plan(const Scene& scene, uint32_t slot, uint32_t steps);
  // Records the steps planned into `slot` and marks them recorded.
  void record(const Scene& scene, VkCommandBuffer commands, uint32_t slot);
  void runBlocking(const Scene& scene, uint64_t steps, const detail::TimestampPair* timer,
                   double* seconds);
};

GpuSimulation::GpuSimulation(Device& device, const Scene& scene,
                             const GpuSimulationOptions& options)
    : Simulation(scene), impl_(std::make_unique<Impl>(device.context(), options)) {
  detail::requireSupported(scene);
  Impl& m = *impl_;
  detail::DeviceContext& c = m.c;
  if (options.framesInFlight < 1 || options.framesInFlight > 16)
    throw InvalidArgument("framesInFlight",
                          "expected 1 to 16, got " + std::to_string(options.framesInFlight));
  if (options.maxStepsPerFrame < 1 || options.maxStepsPerFrame > 65536)
    throw InvalidArgument("maxStepsPerFrame",
                          "expected 1 to 65536, got " + std::to_string(options.maxStepsPerFrame));
  if (options.stepsPerDispatch < 1 || options.stepsPerDispatch > kMaxStepsPerDispatch)
    throw InvalidArgument("stepsPerDispatch",
                          "expected 1 to 256, got " + std::to_string(options.stepsPerDispatch));
  const uint64_t total = scene.particles();
  const uint64_t limit = device.maxParticles();
  if (total > limit)
    throw InvalidArgument("particles", std::to_string(total) + " particles need " +
                                           std::to_string((total * kParticleBytes) >> 20) +
                                           " MiB; device '" + c.properties.deviceName +
                                           "' allows at most " + std::to_string(limit));

  const uint32_t perChunk = device.particlesPerChunk();
  for (uint64_t first = 0; first < total; first += perChunk) {
    const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(perChunk, total - first));
    m.buffers.emplace_back(c, VkDeviceSize{count} * kParticleBytes,
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           MemoryUse::Device);
    m.views.push_back(detail::createTexelView(c, m.buffers.back().get(), count * kParticleBytes));
    m.chunks.push_back({first, count, m.buffers.back().get(), m.views.back()});
  }
  const VkDeviceSize chunkBytes = VkDeviceSize{m.chunks.front().count} * kParticleBytes;
  m.upload = Buffer(c, chunkBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
  m.readback = Buffer(c, chunkBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback);

  const VkDeviceSize alignment =
      std::max<VkDeviceSize>(c.limits.minStorageBufferOffsetAlignment, 1);
  VkDeviceSize offset = 0;
  for (uint32_t s = 0; s <= options.framesInFlight; ++s) {
    ScheduleSlot slot;
    slot.offset = offset;
    slot.capacity = s < options.framesInFlight ? options.maxStepsPerFrame : kBlockingSteps;
    slot.births.assign(slot.capacity + 1, 0);
    offset += (slot.capacity * sizeof(gpu::EmitEntry) + alignment - 1) / alignment * alignment;
    m.slots.push_back(std::move(slot));
  }
  m.schedule = Buffer(c, offset, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload);

  m.setLayout = detail::createPushLayout(
      c,
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  m.pipelineLayout = detail::createPipelineLayout(c, m.setLayout, VK_SHADER_STAGE_COMPUTE_BIT,
                                                  sizeof(gpu::StepParams));
  m.pipeline = detail::createComputePipeline(c, m.pipelineLayout, LAVA_SPIRV(spirv::kStepCompSpv),
                                             {gpu::kWorkgroupSize});
  setState(initialState(scene));
}

GpuSimulation::~GpuSimulation() = default;

std::string GpuSimulation::name() const {
  return std::string("gpu (") + impl_->c.properties.deviceName + ")";
}

const std::vector<ParticleChunk>& GpuSimulation::chunks() const {
  return impl_->chunks;
}

const GpuSimulationOptions& GpuSimulation::options() const {
  return impl_->options;
}

const std::vector<EmitterClock>& GpuSimulation::clocks() const {
  return impl_->clocks;
}

uint64_t GpuSimulation::step() const {
  return impl_->step;
}

void GpuSimulation::setScene(const Scene& scene) {
  Simulation::setScene(scene);
}

void GpuSimulation::Impl::plan(const Scene& scene, uint32_t index, uint32_t steps) {
  ScheduleSlot& slot = slots[index];
  if (steps > slot.capacity)
    throw InvalidArgument("steps", "at most " + std::to_string(slot.capacity) +
                                       " steps per update, got " + std::to_string(steps));
  auto* entries =
      reinterpret_cast<gpu::EmitEntry*>(static_cast<char*>(schedule.mapped()) + slot.offset);
  const Emitter& e = scene.emitters[0];
  const uint64_t period = detail::burstPeriod(e, scene.dt);
  uint64_t births = 0;  // only differences within one dispatch matter
  for (uint32_t k = 0; k < steps; ++k) {
    const detail::Births b = detail::advanceClock(clocks[0], e, scene.h(), period, step + k);
    entries[k].ring = {b.head, b.count, static_cast<uint32_t>(b.firstSerial),
                       static_cast<uint32_t>(b.firstSerial >> 32)};
    entries[k].sums = {static_cast<uint32_t>(births), 0u, 0u, 0u};
    slot.births[k] = births;
    births += b.count;
  }
  slot.births[steps] = births;
  slot.planned = steps;
  step += steps;
  schedule.flush();
}

void GpuSimulation::Impl::record(const Scene& scene, VkCommandBuffer commands, uint32_t index) {
  ScheduleSlot& slot = slots[index];
  if (slot.planned == 0) return;
  c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  gpu::StepParams params = stepParams(scene);
  const VkDeviceSize scheduleBytes = slot.capacity * sizeof(gpu::EmitEntry);
  for (uint32_t done = 0, steps = 0; done < slot.planned; done += steps) {
    // At most stepsPerDispatch steps and fewer than 2^31 births (the shader's 32-bit sums).
    steps = 1;
    while (done + steps < slot.planned && steps < options.stepsPerDispatch &&
           slot.births[done + steps + 1] - slot.births[done] < (uint64_t{1} << 31))
      ++steps;
    // RAW/WAW: an earlier dispatch or upload wrote the particles this one reads and writes;
    // WAR: a draw, splat, or read-back copy read them.
    detail::memoryBarrier(c, commands,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                              VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                              VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                          VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    params.run.z = done;
    params.run.w = steps;
    for (const ParticleChunk& chunk : chunks) {
      params.chunk = {static_cast<uint32_t>(chunk.first), chunk.count, 0u, 0u};
      detail::PushDescriptors()
          .buffer(gpu::kParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.buffer, 0,
                  chunk.count * kParticleBytes)
          .buffer(gpu::kScheduleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, schedule.get(),
                  slot.offset, scheduleBytes)
          .texels(gpu::kParticleTexelBinding, chunk.texels)
          .push(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout);
      c.vk.CmdPushConstants(commands, pipelineLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                            sizeof(params), &params);
      const uint64_t invocations =
          (uint64_t{chunk.count} + gpu::kParticlesPerInvocation - 1) / gpu::kParticlesPerInvocation;
      c.vk.CmdDispatch(commands, detail::groupCount(invocations, gpu::kWorkgroupSize), 1, 1);
    }
  }
  slot.planned = 0;
}

void GpuSimulation::update(uint32_t frame, uint32_t steps) {
  if (frame >= impl_->options.framesInFlight)
    throw InvalidArgument("frame", "expected a frame slot in [0, " +
                                       std::to_string(impl_->options.framesInFlight - 1) +
                                       "], got " + std::to_string(frame));
  impl_->plan(scene_, frame, steps);
}

void GpuSimulation::recordSimulate(VkCommandBuffer commands, uint32_t frame) {
  if (frame >= impl_->options.framesInFlight)
    throw InvalidArgument("frame", "expected a frame slot in [0, " +
                                       std::to_string(impl_->options.framesInFlight - 1) +
                                       "], got " + std::to_string(frame));
  impl_->record(scene_, commands, frame);
}

void GpuSimulation::Impl::runBlocking(const Scene& scene, uint64_t steps,
                                      const detail::TimestampPair* timer, double* seconds) {
  while (steps > 0) {
    const uint32_t batch = static_cast<uint32_t>(std::min<uint64_t>(steps, kBlockingSteps));
    plan(scene, blockingSlot(), batch);
    c.submitNow([&](VkCommandBuffer commands) {
      if (timer) timer->recordStart(commands);
      record(scene, commands, blockingSlot());
      if (timer) timer->recordEnd(commands);
    });
    if (timer) *seconds += timer->seconds();
    steps -= batch;
  }
}

void GpuSimulation::advance(uint64_t steps) {
  impl_->runBlocking(scene_, steps, nullptr, nullptr);
}

double GpuSimulation::advanceTimed(uint64_t steps) {
  const detail::TimestampPair timer(impl_->c);
  double seconds = 0.0;
  impl_->runBlocking(scene_, steps, &timer, &seconds);
  return seconds;
}

void GpuSimulation::setState(const State& state) {
  checkState(scene_, state);
  Impl& m = *impl_;
  for (const ParticleChunk& chunk : m.chunks) {
    const VkDeviceSize bytes = chunk.count * kParticleBytes;
    std::memcpy(m.upload.mapped(), state.particles.data() + chunk.first, bytes);
    m.upload.flush();
    m.c.submitNow([&](VkCommandBuffer commands) {
      // WAW/WAR: earlier dispatches wrote, and draws or copies read, what is overwritten here.
      detail::memoryBarrier(
          m.c, commands,
          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
              VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
          VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
      const VkBufferCopy region{0, 0, bytes};
      m.c.vk.CmdCopyBuffer(commands, m.upload.get(), chunk.buffer, 1, &region);
    });
  }
  m.clocks = state.clocks;
  m.step = state.step;
}

State GpuSimulation::state() {
  Impl& m = *impl_;
  State out;
  out.particles.resize(scene_.particles());
  for (const ParticleChunk& chunk : m.chunks) {
    const VkDeviceSize bytes = chunk.count * kParticleBytes;
    m.c.submitNow([&](VkCommandBuffer commands) {
      // RAW: step.comp (or an upload) wrote the particles this copy reads.
      detail::memoryBarrier(m.c, commands,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
      const VkBufferCopy region{0, 0, bytes};
      m.c.vk.CmdCopyBuffer(commands, chunk.buffer, m.readback.get(), 1, &region);
      // RAW: the host reads what the copy wrote.
      detail::memoryBarrier(m.c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                            VK_ACCESS_HOST_READ_BIT);
    });
    m.readback.invalidate();
    std::memcpy(out.particles.data() + chunk.first, m.readback.mapped(), bytes);
  }
  out.clocks = m.clocks;
  out.step = m.step;
  return out;
}

}  // namespace lava
