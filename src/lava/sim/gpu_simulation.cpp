// The Vulkan backend: step.comp over the particles, held in chunks of at most one binding,
// one texel view, one dispatch and one allocation each; many steps per dispatch. The host
// plans each frame's emission into that frame's slot of a host-visible schedule, and writes
// the scene's parameters into that slot's uniform buffer.
#include <algorithm>
#include <cstring>

#include <map>

#include "common/check.h"
#include "emission.h"
#include "flow/gpu_flow.h"
#include "lava/error.h"
#include "lava/simulation.h"
#include "scene_params.h"
#include "shared.h"
#include "vulkan/buffer.h"
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

// step.comp for a scene: with the birth search and emission, and without (for the
// workgroups no birth of a dispatch lands on).
struct StepPipelines {
  VkPipeline births = VK_NULL_HANDLE;
  VkPipeline none = VK_NULL_HANDLE;
};

// One slot of the schedule: each emitter's entries for the steps planned into it (a region
// of `capacity` entries per emitter), the scene's parameters for them, and on the host each
// emitter's births before each entry (to keep a dispatch under 2^31 births).
struct ScheduleSlot {
  ScheduleSlot(detail::DeviceContext& c, size_t emitters, uint32_t entries)
      : capacity(entries),
        births(emitters, std::vector<uint64_t>(entries + 1, 0)),
        heads(emitters, std::vector<uint32_t>(entries, 0)),
        schedule(c, emitters * entries * sizeof(gpu::EmitEntry), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryUse::Upload),
        sceneParams(c, sizeof(gpu::SceneParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                    MemoryUse::Upload),
        sets(c) {}

  uint32_t capacity = 0;                      // entries per emitter
  uint32_t planned = 0;                       // steps the last update() wrote, until recorded
  std::vector<std::vector<uint64_t>> births;  // [emitter][i]: births before entry i
  std::vector<std::vector<uint32_t>> heads;   // [emitter][i]: ring slot of entry i's first birth
  std::vector<uint32_t> rings;                // [emitter]: its first slot
  StepPipelines pipelines;                    // for the scene planned into it
  Buffer schedule;                            // the entries, host-written
  Buffer sceneParams;                         // the scene's parameters, host-written
  Buffer flowParams;                          // the flow's, host-written (scenes with a flow)
  detail::DescriptorArena sets;               // without push descriptors
  // The flow emitters' births of each planned step, and the implicit flow's staging: what
  // the host steps and the recording copies to the device (GpuFlow).
  std::vector<std::vector<detail::Births>> flowBirths;
  Buffer flowStaging;
};

// Half-open ranges of workgroups of one step dispatch.
struct GroupRange {
  uint32_t begin, end;
};

// The workgroups of `chunk` some of whose particles are born in entries [from, to) of
// `slot`: births fill each emitter's ring contiguously from the first entry's head, and
// invocation a steps the chunk's particles a + j * stride (j < kParticlesPerInvocation).
// Sorted and merged, gaps of fewer than kMinFastGroups closed (a dispatch and barrier of
// their own would cost more than they save); at most kMaxRanges ranges, else the whole chunk.
std::vector<GroupRange> birthGroups(const ScheduleSlot& slot, const ParticleChunk& chunk,
                                    const Scene& scene, uint32_t from, uint32_t to) {
  const uint64_t stride =
      (uint64_t{chunk.count} + gpu::kParticlesPerInvocation - 1) / gpu::kParticlesPerInvocation;
  const uint32_t groups = detail::groupCount(stride, gpu::kWorkgroupSize);
  std::vector<GroupRange> ranges;
  const auto invocations = [&](uint64_t a0, uint64_t a1) {  // invocations [a0, a1)
    ranges.push_back({static_cast<uint32_t>(a0 / gpu::kWorkgroupSize),
                      static_cast<uint32_t>((a1 + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize)});
  };
  const auto slots = [&](uint64_t g0, uint64_t g1) {  // state slots [g0, g1)
    const uint64_t l0 = std::max(g0, chunk.first), l1 = std::min(g1, chunk.first + chunk.count);
    if (l0 >= l1) return;
    const uint64_t a0 = (l0 - chunk.first) % stride, a1 = (l1 - 1 - chunk.first) % stride + 1;
    if (l1 - l0 >= stride) {
      invocations(0, stride);
    } else if (a0 < a1) {
      invocations(a0, a1);
    } else {
      invocations(a0, stride);
      invocations(0, a1);
    }
  };
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    if (scene.emitters[k].flow) continue;  // born by flow.comp
    const uint64_t total = slot.births[k][to] - slot.births[k][from];
    if (total == 0) continue;
    const uint64_t capacity = scene.emitters[k].particles;
    const uint64_t born = std::min(total, capacity);
    const uint64_t head = slot.heads[k][from], ring = slot.rings[k];
    slots(ring + head, ring + std::min(head + born, capacity));
    if (head + born > capacity) slots(ring, ring + head + born - capacity);
  }
  std::sort(ranges.begin(), ranges.end(),
            [](const GroupRange& a, const GroupRange& b) { return a.begin < b.begin; });
  // A run of workgroups without births smaller than this is not worth a dispatch of its own.
  constexpr uint32_t kMinFastGroups = 32;
  constexpr size_t kMaxRanges = 8;
  std::vector<GroupRange> merged;
  for (const GroupRange& r : ranges) {
    if (!merged.empty() && r.begin < merged.back().end + kMinFastGroups) {
      merged.back().end = std::max(merged.back().end, r.end);
    } else {
      merged.push_back(r);
    }
  }
  if (!merged.empty()) {
    if (merged.front().begin < kMinFastGroups) merged.front().begin = 0;
    if (groups - merged.back().end < kMinFastGroups) merged.back().end = groups;
  }
  if (merged.size() > kMaxRanges) merged.assign(1, GroupRange{0, groups});
  return merged;
}

detail::Spirv stepShader(const detail::DeviceContext& c) {
  return detail::withFloatControls(
      c, LAVA_SPIRV(spirv::kStepCompSpv), LAVA_SPIRV(spirv::kStepSignedZeroSpv),
      LAVA_SPIRV(spirv::kStepRteSpv), LAVA_SPIRV(spirv::kStepPlainSpv));
}

}  // namespace

struct GpuSimulation::Impl {
  detail::DeviceContext& c;
  GpuSimulationOptions options;
  std::vector<Buffer> buffers;  // one per chunk
  std::vector<detail::UniqueBufferView> views;
  std::vector<ParticleChunk> chunks;
  Buffer upload, readback;  // one chunk's worth each, for setState() and state()
  // The host's frame slots (as many as the device has had; made on their first update()),
  // and the blocking helpers' own.
  std::vector<std::unique_ptr<ScheduleSlot>> frames;
  std::unique_ptr<ScheduleSlot> blocking;
  detail::UniqueDescriptorSetLayout setLayout;
  detail::UniquePipelineLayout pipelineLayout;
  // One pipeline per set of modules a scene used (kept: a frame in flight may use it).
  std::map<detail::Constants, detail::UniquePipeline> pipelines;
  std::unique_ptr<detail::GpuFlow> flow;  // scenes with flow emitters
  std::vector<EmitterClock> clocks;
  uint64_t step = 0;
  bool initPending = true;  // the particles still hold whatever the allocation held

  Impl(detail::DeviceContext& context, const GpuSimulationOptions& o) : c(context), options(o) {}

  static constexpr uint32_t kBlockingSlot = UINT32_MAX;
  ScheduleSlot& slot(uint32_t index) { return index == kBlockingSlot ? *blocking : *frames[index]; }
  // Creates what is missing (`none` too unless onlyBirths: a run that never steps need not
  // compile it).
  StepPipelines pipelinesFor(const Scene& scene, bool onlyBirths = false);
  void plan(const Scene& scene, uint32_t slot, uint32_t steps);
  uint32_t stepsInDispatch(const ScheduleSlot& slot, uint32_t done) const;
  void bindChunk(VkCommandBuffer commands, const Scene& scene, ScheduleSlot& slot,
                 const ParticleChunk& chunk) const;
  // Records the steps planned into `slot` and marks them recorded.
  void record(const Scene& scene, VkCommandBuffer commands, uint32_t slot);
  void runBlocking(const Scene& scene, uint64_t steps, const detail::TimestampPair* timer,
                   double* seconds);
  // Records the initial state's writes when they are still due (see recordInit()).
  void recordInit(VkCommandBuffer commands);
};

void GpuSimulation::Impl::recordInit(VkCommandBuffer commands) {
  if (!initPending) return;
  // Every slot unborn: one block of unborn particles recorded into the command buffer
  // itself (vkCmdUpdateBuffer's largest), then copied over every chunk; no staging memory
  // that would have to outlive the host's submission.
  constexpr VkDeviceSize kBlock = 65536;
  const std::vector<Particle> unborn(kBlock / kParticleBytes,
                                     Particle{0.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  const ParticleChunk& source = chunks.front();
  const VkDeviceSize block = std::min<VkDeviceSize>(kBlock, source.count * kParticleBytes);
  c.vk.CmdUpdateBuffer(commands, source.buffer, 0, block, unborn.data());
  // RAW: the copies read the block just written.
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  std::vector<VkBufferCopy> regions;
  for (const ParticleChunk& chunk : chunks) {
    regions.clear();
    const VkDeviceSize bytes = chunk.count * kParticleBytes;
    for (VkDeviceSize at = chunk.buffer == source.buffer ? block : 0; at < bytes; at += block)
      regions.push_back({0, at, std::min(block, bytes - at)});
    if (!regions.empty())
      c.vk.CmdCopyBuffer(commands, source.buffer, chunk.buffer, uint32_t(regions.size()),
                         regions.data());
  }
  if (flow) flow->recordInit(commands, source.buffer, block);  // the flow's copy unborn too
  // RAW: steps, draws and read-backs read the particles written here.
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                            VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
  initPending = false;
}

namespace {

// InvalidArgument naming the option that is out of range.
void checkOptions(const GpuSimulationOptions& options) {
  if (options.maxStepsPerFrame < 1 || options.maxStepsPerFrame > 65536)
    throw InvalidArgument("maxStepsPerFrame",
                          "expected 1 to 65536, got " + std::to_string(options.maxStepsPerFrame));
  if (options.stepsPerDispatch < 1 || options.stepsPerDispatch > kMaxStepsPerDispatch)
    throw InvalidArgument("stepsPerDispatch",
                          "expected 1 to 256, got " + std::to_string(options.stepsPerDispatch));
  if (options.maxParticleStepsPerSubmission < 1)
    throw InvalidArgument("maxParticleStepsPerSubmission", "expected at least 1, got 0");
}

// The particles a buffer holds: the device's, or fewer whole workgroups when asked.
uint32_t particlesPerChunk(const Device& device, const GpuSimulationOptions& options) {
  const uint32_t perChunk = device.particlesPerChunk();
  if (options.maxParticlesPerChunk == 0) return perChunk;
  if (options.maxParticlesPerChunk < gpu::kWorkgroupSize)
    throw InvalidArgument("maxParticlesPerChunk",
                          "expected 0 or at least " + std::to_string(gpu::kWorkgroupSize) +
                              ", got " + std::to_string(options.maxParticlesPerChunk));
  return std::min(perChunk, options.maxParticlesPerChunk -
                                options.maxParticlesPerChunk % gpu::kWorkgroupSize);
}

}  // namespace

GpuSimulation::GpuSimulation(Device& device, const Scene& scene,
                             const GpuSimulationOptions& options)
    : Simulation(scene), impl_(std::make_unique<Impl>(device.context(), options)) {
  Impl& m = *impl_;
  detail::DeviceContext& c = m.c;
  checkOptions(options);
  const uint64_t total = scene.particles();
  const uint64_t limit = device.maxParticles();
  if (total > limit)
    throw InvalidArgument("particles", std::to_string(total) + " particles need " +
                                           std::to_string((total * kParticleBytes) >> 20) +
                                           " MiB; device '" + c.properties.deviceName +
                                           "' allows at most " + std::to_string(limit));

  const uint32_t perChunk = particlesPerChunk(device, options);
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

  m.blocking = std::make_unique<ScheduleSlot>(c, scene.emitters.size(), kBlockingSteps);

  m.setLayout = detail::createSetLayout(
      c,
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  m.pipelineLayout = detail::createPipelineLayout(c, m.setLayout, VK_SHADER_STAGE_COMPUTE_BIT,
                                                  sizeof(gpu::StepParams));
  if (scene.flows()) m.flow = std::make_unique<detail::GpuFlow>(c, scene);
  m.pipelinesFor(scene, true);
  // The initial state: the clocks here; the particles' writes are recorded by the first
  // recording or blocking call (recordInit()).
  const State initial = initialState(scene);
  m.clocks = initial.clocks;
  m.step = initial.step;
}

GpuSimulation::~GpuSimulation() = default;

std::string GpuSimulation::name() const {
  return std::string("gpu (") + impl_->c.properties.deviceName + ")" +
         (impl_->flow && impl_->flow->onHost() ? ", the implicit flow on the host" : "");
}

const std::vector<ParticleChunk>& GpuSimulation::chunks() const {
  return impl_->chunks;
}

GpuSimulation::FlowBuffers GpuSimulation::flowBuffers() const {
  return impl_->flow ? impl_->flow->buffers() : FlowBuffers{};
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
  impl_->pipelinesFor(scene_);  // created now, not while recording
  if (impl_->flow) impl_->flow->setScene(scene_);
}

StepPipelines GpuSimulation::Impl::pipelinesFor(const Scene& scene, bool onlyBirths) {
  StepPipelines both;
  for (uint32_t births : {1u, 0u}) {
    if (births == 0 && onlyBirths) break;
    detail::Constants constants = detail::stepConstants(scene);
    constants.resize(gpu::kFlowEmittersConstant + 1, 0u);
    constants[gpu::kBirthsConstant] = births;
    for (size_t k = 0; k < scene.emitters.size(); ++k)
      constants[gpu::kFlowEmittersConstant] |= scene.emitters[k].flow ? 1u << k : 0u;
    auto it = pipelines.find(constants);
    if (it == pipelines.end())
      it = pipelines
               .emplace(constants,
                        detail::createComputePipeline(c, pipelineLayout, stepShader(c), constants))
               .first;
    (births ? both.births : both.none) = it->second;
  }
  return both;
}

void GpuSimulation::Impl::plan(const Scene& scene, uint32_t index, uint32_t steps) {
  ScheduleSlot& slot = this->slot(index);
  if (steps > slot.capacity)
    throw InvalidArgument("steps", "at most " + std::to_string(slot.capacity) +
                                       " steps per update, got " + std::to_string(steps));
  auto* entries = static_cast<gpu::EmitEntry*>(slot.schedule.mapped());
  const gpu::SceneParams params = detail::sceneParams(scene);
  slot.rings.assign(scene.emitters.size(), 0);
  slot.flowBirths.resize(scene.emitters.size());
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    slot.flowBirths[k].clear();
    slot.rings[k] = params.emitters[k].ring.w;  // the first slot, as step.comp reads it
    const Emitter& e = scene.emitters[k];
    const uint64_t period = detail::burstPeriod(e, scene.dt);
    gpu::EmitEntry* region = entries + k * slot.capacity;
    std::vector<uint64_t>& before = slot.births[k];
    uint64_t births = 0;  // only differences within one dispatch matter
    for (uint32_t i = 0; i < steps; ++i) {
      const detail::Births b = detail::advanceClock(clocks[k], e, scene.h(), period, step + i);
      if (e.flow) slot.flowBirths[k].push_back(b);
      region[i].ring = {b.head, b.count, static_cast<uint32_t>(b.firstSerial),
                        static_cast<uint32_t>(b.firstSerial >> 32)};
      region[i].sums = {static_cast<uint32_t>(births), 0u, 0u, 0u};
      before[i] = births;
      slot.heads[k][i] = b.head;
      births += b.count;
    }
    before[steps] = births;
  }
  std::memcpy(slot.sceneParams.mapped(), &params, sizeof(params));
  if (flow) {
    if (!slot.flowParams.get())
      slot.flowParams =
          Buffer(c, sizeof(gpu::FlowParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryUse::Upload);
    std::memcpy(slot.flowParams.mapped(), &flow->params(), sizeof(gpu::FlowParams));
    slot.flowParams.flush();
  }
  slot.pipelines = pipelinesFor(scene);
  slot.planned = steps;
  step += steps;
  slot.schedule.flush();
  slot.sceneParams.flush();
}

// As many of the slot's steps from `done` as one dispatch may take: at most
// stepsPerDispatch, and fewer than 2^31 births of each emitter (the shader's 32-bit sums).
uint32_t GpuSimulation::Impl::stepsInDispatch(const ScheduleSlot& slot, uint32_t done) const {
  const auto fits = [&slot](uint32_t from, uint32_t to) {
    for (const std::vector<uint64_t>& births : slot.births)
      if (births[to] - births[from] >= (uint64_t{1} << 31)) return false;
    return true;
  };
  uint32_t steps = 1;
  while (done + steps < slot.planned && steps < options.stepsPerDispatch &&
         fits(done, done + steps + 1))
    ++steps;
  return steps;
}

// The step's descriptors for one chunk: its particles (as storage and as texels), the
// slot's schedule and scene.
void GpuSimulation::Impl::bindChunk(VkCommandBuffer commands, const Scene& scene,
                                    ScheduleSlot& slot, const ParticleChunk& chunk) const {
  const VkDeviceSize scheduleBytes = scene.emitters.size() * slot.capacity * sizeof(gpu::EmitEntry);
  detail::Descriptors()
      .buffer(gpu::kParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.buffer, 0,
              chunk.count * kParticleBytes)
      .buffer(gpu::kScheduleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, slot.schedule.get(), 0,
              scheduleBytes)
      .texels(gpu::kParticleTexelBinding, chunk.texels)
      .buffer(gpu::kSceneBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, slot.sceneParams.get(), 0,
              sizeof(gpu::SceneParams))
      .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout, setLayout, slot.sets);
}

void GpuSimulation::Impl::record(const Scene& scene, VkCommandBuffer commands, uint32_t index) {
  ScheduleSlot& slot = this->slot(index);
  if (slot.planned == 0) return;
  slot.sets.reset();  // the slot's previous submission has finished
  VkPipeline bound = VK_NULL_HANDLE;
  gpu::StepParams params{};
  params.run.z = slot.capacity;
  for (uint32_t done = 0, steps = 0; done < slot.planned; done += steps) {
    steps = stepsInDispatch(slot, done);
    // RAW/WAW: an earlier dispatch or upload wrote the particles this one reads and writes;
    // WAR: a draw, splat, or read-back copy read them.
    beforeCompute(c, commands);
    params.run.x = done;
    params.run.y = steps;
    for (const ParticleChunk& chunk : chunks) {
      params.chunk = {static_cast<uint32_t>(chunk.first), chunk.count, 0u, 0u};
      bindChunk(commands, scene, slot, chunk);
      const uint64_t invocations =
          (uint64_t{chunk.count} + gpu::kParticlesPerInvocation - 1) / gpu::kParticlesPerInvocation;
      const uint32_t groups = detail::groupCount(invocations, gpu::kWorkgroupSize);
      // The workgroups a birth lands on run the full step; the rest, in between, the one
      // without births. Each dispatch covers workgroups [begin, end).
      bool first = true;
      const auto dispatch = [&](VkPipeline pipeline, uint32_t begin, uint32_t end) {
        if (begin >= end) return;
        // The workgroups touch other particles, but the bound buffer is one resource to
        // synchronisation (validation included): WAR/WAW/RAW across the earlier dispatch.
        if (!first)
          detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        first = false;
        if (pipeline != bound)
          c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        bound = pipeline;
        params.chunk.z = begin * gpu::kWorkgroupSize;
        c.vk.CmdPushConstants(commands, pipelineLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                              sizeof(params), &params);
        c.vk.CmdDispatch(commands, end - begin, 1, 1);
      };
      uint32_t next = 0;
      for (const GroupRange& r : birthGroups(slot, chunk, scene, done, done + steps)) {
        dispatch(slot.pipelines.none, next, r.begin);
        dispatch(slot.pipelines.births, r.begin, r.end);
        next = r.end;
      }
      dispatch(slot.pipelines.none, next, groups);
    }
  }
  if (flow)
    flow->record(commands, scene,
                 {slot.schedule.get(), slot.sceneParams.get(), slot.flowParams.get(), slot.capacity,
                  &slot.sets, &slot.flowBirths, &slot.flowStaging},
                 slot.planned, chunks);
  slot.planned = 0;
}

void GpuSimulation::update(uint32_t frame, uint32_t steps) {
  Impl& m = *impl_;
  m.c.checkFrame(frame);
  while (m.frames.size() <= frame)  // a slot's first frame, or more slots than before
    m.frames.push_back(
        std::make_unique<ScheduleSlot>(m.c, scene_.emitters.size(), m.options.maxStepsPerFrame));
  if (m.frames[frame]->planned > 0)  // planning over them would lose those steps
    throw InvalidArgument("frame", "slot " + std::to_string(frame) + " still holds " +
                                       std::to_string(m.frames[frame]->planned) +
                                       " steps of the last update(): record them first "
                                       "(recordSimulate)");
  m.plan(scene_, frame, steps);
}

void GpuSimulation::recordSimulate(VkCommandBuffer commands, uint32_t frame) {
  Impl& m = *impl_;
  m.c.checkFrame(frame);
  m.recordInit(commands);
  if (frame < m.frames.size()) m.record(scene_, commands, frame);  // else nothing planned
}

void GpuSimulation::recordInit(VkCommandBuffer commands) const {
  impl_->recordInit(commands);
}

void GpuSimulation::Impl::runBlocking(const Scene& scene, uint64_t steps,
                                      const detail::TimestampPair* timer, double* seconds) {
  // Submissions of at most maxParticleStepsPerSubmission particle-steps, one step at least.
  const uint64_t most =
      std::max<uint64_t>(options.maxParticleStepsPerSubmission / scene.particles(), 1);
  while (steps > 0) {
    const uint32_t batch = static_cast<uint32_t>(std::min({steps, uint64_t{kBlockingSteps}, most}));
    plan(scene, kBlockingSlot, batch);
    c.submitNow([&](VkCommandBuffer commands) {
      recordInit(commands);
      if (timer) timer->recordStart(commands);
      record(scene, commands, kBlockingSlot);
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
  if (m.flow) m.flow->upload(state);  // its particles and heat; the grid's counts 0
  m.clocks = state.clocks;
  m.step = state.step;
  m.initPending = false;  // every chunk was written
}

State GpuSimulation::state() {
  Impl& m = *impl_;
  State out;
  out.particles.resize(scene_.particles());
  if (m.initPending) m.c.submitNow([&](VkCommandBuffer commands) { m.recordInit(commands); });
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
  if (scene_.flow) {  // slots of other emitters (or a flow without emitters): 0 K, no crust
    out.temperature.assign(out.particles.size(), 0.0f);
    out.crust.assign(out.particles.size(), 0);
  }
  if (m.flow) m.flow->download(out);
  return out;
}

}  // namespace lava
