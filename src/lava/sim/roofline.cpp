// The ceilings of `lava bench`: a copy kernel moving the bytes of one unfused step, in
// chunks of one allocation each like the simulation, and the same copy on the CPU; and the
// CPU kernels' step alone on a block in L1.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "lava/bench.h"
#include "reference.h"
#include "scene_params.h"
#include "shared.h"
#include "simd.h"
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

}  // namespace

double gpuCopySeconds(Device& device, uint64_t particles, int passes) {
  const detail::DeviceContext& c = device.context();
  const auto setLayout = detail::createSetLayout(
      c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  const auto layout =
      detail::createPipelineLayout(c, setLayout, VK_SHADER_STAGE_COMPUTE_BIT, sizeof(glm::uvec4));
  const auto pipeline = detail::createComputePipeline(c, layout, LAVA_SPIRV(spirv::kCopyCompSpv),
                                                      {gpu::kWorkgroupSize});
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
  const detail::TimestampPair timer(c);
  std::vector<double> times;
  detail::DescriptorArena sets(c);
  for (int pass = -1; pass < passes; ++pass) {  // pass -1 warms up
    sets.reset();                               // the previous pass has finished
    c.submitNow([&](VkCommandBuffer commands) {
      // WAW: the previous pass wrote the destination this one overwrites.
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT);
      timer.recordStart(commands);
      c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
      for (const Chunk& chunk : chunks) {
        const glm::uvec4 range{0u, chunk.count, 0u, 0u};
        detail::Descriptors()
            .buffer(gpu::kCopySourceBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.source.get())
            .buffer(gpu::kCopyDestinationBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                    chunk.destination.get())
            .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout, setLayout, sets);
        c.vk.CmdPushConstants(commands, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(range),
                              &range);
        c.vk.CmdDispatch(commands, detail::groupCount(chunk.count, gpu::kWorkgroupSize), 1, 1);
      }
      timer.recordEnd(commands);
    });
    if (pass >= 0) times.push_back(timer.seconds());
  }
  return median(times);
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

double gpuComputeUpdatesPerSecond(Device& device, const Scene& scene,
                                  const std::vector<Particle>& start, uint32_t steps, int passes) {
  const uint64_t particles = start.size();
  const detail::DeviceContext& c = device.context();
  const auto setLayout = detail::createSetLayout(
      c,
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
       VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  const auto layout = detail::createPipelineLayout(c, setLayout, VK_SHADER_STAGE_COMPUTE_BIT,
                                                   sizeof(gpu::StepParams));
  const auto pipeline = detail::createComputePipeline(
      c, layout, LAVA_SPIRV(spirv::kStepKernelOnlySpv), detail::stepConstants(scene));
  detail::Buffer params(c, sizeof(gpu::SceneParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                        detail::MemoryUse::Upload);
  const gpu::SceneParams sceneParams = detail::sceneParams(scene);
  std::memcpy(params.mapped(), &sceneParams, sizeof(sceneParams));
  params.flush();
  struct Chunk {
    detail::Buffer particles, source;
    detail::UniqueBufferView texels;
    uint32_t count;
  };
  std::vector<Chunk> chunks;
  for (const auto& [first, count] : chunkRanges(device, particles)) {
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
  const detail::TimestampPair timer(c);
  std::vector<double> times;
  detail::DescriptorArena sets(c);
  for (int pass = -1; pass < passes; ++pass) {  // pass -1 warms up
    sets.reset();                               // the previous pass has finished
    c.submitNow([&](VkCommandBuffer commands) {
      // Each pass from the start state, so it steps what the timed run stepped (WAW/WAR: the
      // previous pass read and wrote the particles).
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
      for (const Chunk& chunk : chunks) {
        const VkBufferCopy region{0, 0, VkDeviceSize{chunk.count} * sizeof(Particle)};
        c.vk.CmdCopyBuffer(commands, chunk.source.get(), chunk.particles.get(), 1, &region);
      }
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
      timer.recordStart(commands);
      c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
      for (const Chunk& chunk : chunks) {
        gpu::StepParams push{};
        push.run = {0u, pass < 0 ? std::min(steps, 64u) : steps, 0u, 0u};
        push.chunk = {0u, chunk.count, 0u, 0u};
        detail::Descriptors()
            .buffer(gpu::kParticleBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.particles.get(),
                    0, VkDeviceSize{chunk.count} * sizeof(Particle))
            .texels(gpu::kParticleTexelBinding, chunk.texels.get())
            .buffer(gpu::kSceneBinding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, params.get(), 0,
                    sizeof(gpu::SceneParams))
            .bind(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout, setLayout, sets);
        c.vk.CmdPushConstants(commands, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push),
                              &push);
        const uint64_t invocations = (uint64_t{chunk.count} + gpu::kParticlesPerInvocation - 1) /
                                     gpu::kParticlesPerInvocation;
        c.vk.CmdDispatch(commands, detail::groupCount(invocations, gpu::kWorkgroupSize), 1, 1);
      }
      timer.recordEnd(commands);
    });
    if (pass >= 0) times.push_back(timer.seconds());
  }
  return double(particles) * double(steps) / median(times);
}

}  // namespace lava
