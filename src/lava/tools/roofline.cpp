// The ceilings of `lava bench`: a copy kernel moving the bytes of one unfused step, in
// chunks of one allocation each like the simulation, and the same copy on the CPU; the
// CPU kernels' step alone on a block in L1; and the flow's density sum alone over
// neighbour lists made beforehand (flow_pairs.comp on the GPU).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>
#include <unordered_map>
#include <vector>

#include "flow/flow.h"
#include "lava/bench.h"
#include "lava/error.h"
#include "shared.h"
#include "sim/reference.h"
#include "sim/scene_params.h"
#include "sim/simd.h"
#include "vulkan/buffer.h"
#include "vulkan/commands.h"
#include "vulkan/pipeline.h"
#include "vulkan/shaders.h"
#include "vulkan/timestamps.h"

namespace lava {
namespace {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// [first, first + count) of each chunk of `particles`, chunked as a simulation is.
std::vector<std::pair<uint64_t, uint32_t>> chunkRanges(Device& device, uint64_t particles) {
  std::vector<std::pair<uint64_t, uint32_t>> ranges;
  const uint32_t perChunk = device.particlesPerChunk();
  for (uint64_t first = 0; first < particles; first += perChunk)
    ranges.emplace_back(first,
                        static_cast<uint32_t>(std::min<uint64_t>(perChunk, particles - first)));
  return ranges;
}

uint64_t cellKey(const detail::Cell& c) {
  const auto axis = [](int32_t v) { return uint64_t(uint32_t(v + (1 << 20))) & 0x1fffff; };
  return axis(c.x) | axis(c.y) << 21 | axis(c.z) << 42;
}

// The median device time of `passes` submissions, after one more to warm up (pass -1):
// each records prepare(commands), untimed, then work(commands, pass) between two timestamps.
// The descriptor sets are reset before each (the previous submission has finished).
template <class Prepare, class Work>
double medianSeconds(const detail::DeviceContext& c, detail::DescriptorArena& sets, int passes,
                     const Prepare& prepare, const Work& work) {
  const detail::TimestampPair timer(c);
  std::vector<double> times;
  for (int pass = -1; pass < passes; ++pass) {
    sets.reset();
    c.submitNow([&](VkCommandBuffer commands) {
      prepare(commands);
      timer.recordStart(commands);
      work(commands, pass);
      timer.recordEnd(commands);
    });
    if (pass >= 0) times.push_back(timer.seconds());
  }
  return median(times);
}

// WAW: the previous pass wrote what this one overwrites.
void afterThePreviousPass(const detail::DeviceContext& c, VkCommandBuffer commands) {
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT);
}

float invRadius(const Scene& scene) {
  if (!scene.flow) throw InvalidArgument("scene", "has no [flow]: it has no neighbour pairs");
  return 1.0f / scene.flow->radius;
}

// A compute kernel as every ceiling here runs one: one set of `bindings` and `pushBytes` of
// push constants, both for the compute stage only.
struct Kernel {
  detail::UniqueDescriptorSetLayout setLayout;
  detail::UniquePipelineLayout layout;
  detail::UniquePipeline pipeline;
};

Kernel createKernel(const detail::DeviceContext& c,
                    std::initializer_list<VkDescriptorType> bindings, uint32_t pushBytes,
                    detail::Spirv shader, const detail::Constants& constants) {
  Kernel k;
  k.setLayout = detail::createSetLayout(c, bindings, VK_SHADER_STAGE_COMPUTE_BIT);
  k.layout = detail::createPipelineLayout(c, k.setLayout, VK_SHADER_STAGE_COMPUTE_BIT, pushBytes);
  k.pipeline = detail::createComputePipeline(c, k.layout, shader, constants);
  return k;
}

}  // namespace

double gpuCopySeconds(Device& device, uint64_t particles, int passes) {
  const detail::DeviceContext& c = device.context();
  const Kernel k =
      createKernel(c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                   sizeof(glm::uvec4), LAVA_SPIRV(spirv::kCopyCompSpv), {gpu::kWorkgroupSize});
  struct Chunk {
    detail::Buffer source, destination;
    uint32_t count;
  };
  std::vector<Chunk> chunks;
  for (const auto& [first, count] : chunkRanges(device, particles)) {
    const VkDeviceSize bytes = VkDeviceSize{count} * sizeof(Particle);
    chunks.push_back(
        {detail::Buffer(c, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device),
         detail::Buffer(c, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device),
         count});
  }
  detail::DescriptorArena sets(c);
  return medianSeconds(
      c, sets, passes, [&](VkCommandBuffer commands) { afterThePreviousPass(c, commands); },
      [&](VkCommandBuffer commands, int) {
        c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline);
        for (const Chunk& chunk : chunks) {
          const glm::uvec4 range{0u, chunk.count, 0u, 0u};
          detail::Descriptors()
              .buffer(gpu::kCopySourceBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                      chunk.source.get())
              .buffer(gpu::kCopyDestinationBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                      chunk.destination.get())
              .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout, k.setLayout, sets);
          c.vk.CmdPushConstants(commands, k.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(range),
                                &range);
          c.vk.CmdDispatch(commands, detail::groupCount(chunk.count, gpu::kWorkgroupSize), 1, 1);
        }
      });
}

double cpuCopySeconds(uint64_t particles, unsigned threads, int passes) {
  threads = std::max(threads, 1u);
  std::vector<Particle> source(particles, Particle{1, 2, 3, 4, 5, 6, 7, 8});
  std::vector<Particle> destination(particles);
  std::vector<double> times;
  for (int pass = -1; pass < passes; ++pass) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> workers;
    for (unsigned t = 0; t < threads; ++t)
      workers.emplace_back([&, t] {
        const size_t begin = size_t(particles) * t / threads;
        const size_t end = size_t(particles) * (t + 1) / threads;
        std::memcpy(&destination[begin], &source[begin], (end - begin) * sizeof(Particle));
      });
    for (std::thread& w : workers) w.join();
    if (pass >= 0)
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return median(times);
}

double cpuComputeUpdatesPerSecond(const Scene& scene, const std::vector<Particle>& start,
                                  uint64_t steps, unsigned threads, CpuKernel kernel, int passes,
                                  double seconds, const std::string& simdTarget) {
  const detail::SimdTarget target = detail::simdTargetNamed(simdTarget);
  threads = std::max(threads, 1u);
  steps = std::max<uint64_t>(steps, 1);
  const detail::Reference reference(scene);
  const bool scalar = kernel == CpuKernel::Reference;
  // Runs of `steps` steps, each on a fresh block of the start state (a block of particles in
  // the phase the timed run stepped them through; its copy in is 4 KiB per run).
  const size_t blocks = std::max<size_t>(1, start.size() / detail::kSimdBlock);
  auto work = [&](unsigned thread, uint64_t runs) {
    std::vector<Particle> block(detail::kSimdBlock);
    for (uint64_t r = 0; r < runs; ++r) {
      const size_t from = ((r * threads + thread) % blocks) * detail::kSimdBlock;
      for (size_t j = 0; j < block.size(); ++j)
        block[j] = start.empty() ? Particle{} : start[(from + j) % start.size()];
      detail::stepKernelOnly(reference, block.data(), steps, scalar, target);
    }
  };
  uint64_t runs = 1;
  for (;;) {  // runs for about `seconds` per pass
    const auto begin = std::chrono::steady_clock::now();
    work(0, runs);
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    if (took > seconds / 8 || runs > (uint64_t{1} << 30)) {
      runs = std::max<uint64_t>(1, static_cast<uint64_t>(double(runs) * seconds / took));
      break;
    }
    runs *= 4;
  }
  std::vector<double> rates;
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<std::thread> workers;
    const auto begin = std::chrono::steady_clock::now();
    for (unsigned t = 0; t < threads; ++t) workers.emplace_back(work, t, runs);
    for (std::thread& w : workers) w.join();
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    rates.push_back(double(threads) * double(runs) * double(steps) * double(detail::kSimdBlock) /
                    took);
  }
  return median(rates);
}

namespace {

// A chunk of the kernel's run: its particles on the device, and the start state they are
// reset from before each pass.
struct StartChunk {
  detail::Buffer particles, source;
  detail::UniqueBufferView texels;
  uint32_t count;
};

// `start` in chunks as a simulation holds them, each with its start state uploaded.
std::vector<StartChunk> startChunks(Device& device, const std::vector<Particle>& start) {
  const detail::DeviceContext& c = device.context();
  std::vector<StartChunk> chunks;
  for (const auto& [first, count] : chunkRanges(device, start.size())) {
    const VkDeviceSize bytes = VkDeviceSize{count} * sizeof(Particle);
    detail::Buffer source(c, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, detail::MemoryUse::Upload);
    std::memcpy(source.mapped(), &start[first], bytes);
    source.flush();
    detail::Buffer buffer(c, bytes,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                              VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                              VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          detail::MemoryUse::Device);
    auto texels = detail::createTexelView(c, buffer.get(), bytes);
    chunks.push_back({std::move(buffer), std::move(source), std::move(texels), count});
  }
  return chunks;
}

// Each pass from the start state, so it steps what the timed run stepped (WAW/WAR: the
// previous pass read and wrote the particles).
void recordRestart(const detail::DeviceContext& c, VkCommandBuffer commands,
                   const std::vector<StartChunk>& chunks) {
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  for (const StartChunk& chunk : chunks) {
    const VkBufferCopy region{0, 0, VkDeviceSize{chunk.count} * sizeof(Particle)};
    c.vk.CmdCopyBuffer(commands, chunk.source.get(), chunk.particles.get(), 1, &region);
  }
  detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace

double gpuComputeUpdatesPerSecond(Device& device, const Scene& scene,
                                  const std::vector<Particle>& start, uint32_t steps, int passes) {
  const uint64_t particles = start.size();
  const detail::DeviceContext& c = device.context();
  const Kernel k = createKernel(
      c,
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      sizeof(gpu::StepParams), LAVA_SPIRV(spirv::kStepKernelOnlySpv), detail::stepConstants(scene));
  detail::Buffer params(c, sizeof(gpu::SceneParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                        detail::MemoryUse::Upload);
  const gpu::SceneParams sceneParams = detail::sceneParams(scene);
  std::memcpy(params.mapped(), &sceneParams, sizeof(sceneParams));
  params.flush();
  const std::vector<StartChunk> chunks = startChunks(device, start);
  detail::DescriptorArena sets(c);
  const auto reset = [&](VkCommandBuffer commands) { recordRestart(c, commands, chunks); };
  const double seconds =
      medianSeconds(c, sets, passes, reset, [&](VkCommandBuffer commands, int pass) {
        c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline);
        for (const StartChunk& chunk : chunks) {
          gpu::StepParams push{};
          push.run = {0u, pass < 0 ? std::min(steps, 64u) : steps, 0u, 0u};
          push.chunk = {0u, chunk.count, 0u, 0u};
          detail::Descriptors()
              .buffer(gpu::kParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                      chunk.particles.get(), 0, VkDeviceSize{chunk.count} * sizeof(Particle))
              .texels(gpu::kParticleTexelBinding, chunk.texels.get())
              .buffer(gpu::kSceneBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, params.get(), 0,
                      sizeof(gpu::SceneParams))
              .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout, k.setLayout, sets);
          c.vk.CmdPushConstants(commands, k.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push),
                                &push);
          const uint64_t invocations = (uint64_t{chunk.count} + gpu::kParticlesPerInvocation - 1) /
                                       gpu::kParticlesPerInvocation;
          c.vk.CmdDispatch(commands, detail::groupCount(invocations, gpu::kWorkgroupSize), 1, 1);
        }
      });
  return double(particles) * double(steps) / seconds;
}

FlowNeighbours flowNeighbours(const Scene& scene, const State& state) {
  const float inv = invRadius(scene);
  FlowNeighbours out;
  for (const detail::FlowRange& r : detail::flowRanges(scene))
    for (uint64_t i = r.firstSlot; i < r.firstSlot + r.count; ++i)
      if (!(state.particles[i].age < 0.0f)) out.particles.push_back(state.particles[i]);
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  std::vector<detail::Cell> cellOf(out.particles.size());
  for (size_t i = 0; i < out.particles.size(); ++i) {
    const Particle& p = out.particles[i];
    cellOf[i] = detail::cellOf(p.px, p.py, p.pz, inv);
    cells[cellKey(cellOf[i])].push_back(uint32_t(i));
  }
  const float inv2 = inv * inv;
  out.starts.push_back(0);
  for (size_t i = 0; i < out.particles.size(); ++i) {
    const Particle& p = out.particles[i];
    for (int32_t dz = -1; dz <= 1; ++dz)
      for (int32_t dy = -1; dy <= 1; ++dy)
        for (int32_t dx = -1; dx <= 1; ++dx) {
          const detail::Cell c = cellOf[i];
          const auto found = cells.find(cellKey({c.x + dx, c.y + dy, c.z + dz}));
          if (found == cells.end()) continue;
          // The step's neighbour loops read a bucket's first kFlowBucketCap slots.
          const size_t reads = std::min<size_t>(found->second.size(), gpu::kFlowBucketCap);
          for (size_t r = 0; r < reads; ++r) {
            const uint32_t j = found->second[r];
            const Particle& o = out.particles[j];
            const float x = p.px - o.px, y = p.py - o.py, z = p.pz - o.pz;
            if (j != i && 1.0f - ((x * x + y * y) + z * z) * inv2 > detail::kPairCut)
              out.lists.push_back(j);
          }
        }
    out.starts.push_back(uint32_t(out.lists.size()));
  }
  return out;
}

double cpuFlowPairsPerSecond(const Scene& scene, const FlowNeighbours& n, unsigned threads,
                             int passes) {
  const float inv = invRadius(scene);
  const size_t count = n.particles.size();
  std::vector<float> sums(count);
  const auto work = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Particle& p = n.particles[i];
      float theta = 0.0f;
      for (uint32_t e = n.starts[i]; e < n.starts[i + 1]; ++e) {
        const Particle& o = n.particles[n.lists[e]];
        const float x = p.px - o.px, y = p.py - o.py, z = p.pz - o.pz;
        const float q = (x * x + y * y) + z * z;
        const float t = std::max(1.0f - std::sqrt(q) * inv, 0.0f);
        theta += t * t * t;
      }
      sums[i] = theta;
    }
  };
  std::vector<double> rates;
  for (int pass = -1; pass < passes; ++pass) {  // pass -1 warms up
    const auto begin = std::chrono::steady_clock::now();
    std::vector<std::thread> workers;
    for (unsigned t = 1; t < threads; ++t)
      workers.emplace_back(work, count * t / threads, count * (t + 1) / threads);
    work(0, count / std::max(threads, 1u));
    for (std::thread& w : workers) w.join();
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    if (pass >= 0) rates.push_back(double(n.lists.size()) / took);
  }
  return median(rates);
}

double gpuFlowPairsPerSecond(Device& device, const Scene& scene, const FlowNeighbours& n,
                             int passes) {
  const float inv = invRadius(scene);
  const detail::DeviceContext& c = device.context();
  const Kernel k =
      createKernel(c,
                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                   2 * sizeof(glm::uvec4), LAVA_SPIRV(spirv::kFlowPairsSpv), {gpu::kWorkgroupSize});
  const auto upload = [&](const void* data, VkDeviceSize bytes) {
    detail::Buffer b(c, std::max<VkDeviceSize>(bytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                     detail::MemoryUse::Upload);
    if (bytes) std::memcpy(b.mapped(), data, bytes);
    b.flush();
    return b;
  };
  std::vector<glm::vec4> positions;
  for (const Particle& p : n.particles) positions.emplace_back(p.px, p.py, p.pz, 0.0f);
  const detail::Buffer pos = upload(positions.data(), positions.size() * sizeof(glm::vec4));
  const detail::Buffer starts = upload(n.starts.data(), n.starts.size() * sizeof(uint32_t));
  const detail::Buffer lists = upload(n.lists.data(), n.lists.size() * sizeof(uint32_t));
  const detail::Buffer sums(c, std::max<VkDeviceSize>(positions.size() * sizeof(float), 4),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device);
  detail::DescriptorArena sets(c);
  const uint32_t count = uint32_t(n.particles.size());
  const double seconds = medianSeconds(
      c, sets, passes, [&](VkCommandBuffer commands) { afterThePreviousPass(c, commands); },
      [&](VkCommandBuffer commands, int) {
        c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline);
        detail::Descriptors()
            .buffer(0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, pos.get())
            .buffer(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, starts.get())
            .buffer(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, lists.get())
            .buffer(3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sums.get())
            .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout, k.setLayout, sets);
        const glm::uvec4 push[2] = {{count, 0u, 0u, 0u}, {glm::floatBitsToUint(inv), 0u, 0u, 0u}};
        c.vk.CmdPushConstants(commands, k.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push),
                              push);
        c.vk.CmdDispatch(commands, detail::groupCount(count, gpu::kWorkgroupSize), 1, 1);
      });
  return double(n.lists.size()) / seconds;
}

}  // namespace lava
