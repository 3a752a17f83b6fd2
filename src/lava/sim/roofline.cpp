// The ceilings of `lava bench`: a copy kernel moving the bytes of one unfused step, in
// chunks of one allocation each like the simulation, and the same copy on the CPU.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "lava/bench.h"
#include "shared.h"
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

}  // namespace

double gpuCopySeconds(Device& device, uint64_t particles, int passes) {
  const detail::DeviceContext& c = device.context();
  const auto setLayout = detail::createPushLayout(
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
  const uint32_t perChunk = device.particlesPerChunk();
  for (uint64_t first = 0; first < particles; first += perChunk) {
    const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(perChunk, particles - first));
    const VkDeviceSize bytes = VkDeviceSize{count} * sizeof(Particle);
    chunks.push_back(
        {detail::Buffer(c, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device),
         detail::Buffer(c, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, detail::MemoryUse::Device),
         count});
  }
  const detail::TimestampPair timer(c);
  std::vector<double> times;
  for (int pass = -1; pass < passes; ++pass) {  // pass -1 warms up
    c.submitNow([&](VkCommandBuffer commands) {
      // WAW: the previous pass wrote the destination this one overwrites.
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT);
      timer.recordStart(commands);
      c.vk.CmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
      for (const Chunk& chunk : chunks) {
        const glm::uvec4 range{0u, chunk.count, 0u, 0u};
        detail::PushDescriptors()
            .buffer(gpu::kCopySourceBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunk.source.get())
            .buffer(gpu::kCopyDestinationBinding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                    chunk.destination.get())
            .push(c, commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout);
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

}  // namespace lava
