#include "roofline.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "copy_comp.h"
#include "descriptors.h"
#include "gpu_simulator.h"
#include "pipeline.h"
#include "timestamps.h"
#include "vk_check.h"

namespace lava {
namespace {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

CopyKernel::CopyKernel(const Context& context, const Buffer& source, const Buffer& destination,
                       uint32_t particles) {
  VkDevice device = context.device();
  setLayout_ = createStorageSetLayout(device, 2, VK_SHADER_STAGE_COMPUTE_BIT);
  layout_ =
      createPipelineLayout(device, setLayout_, VK_SHADER_STAGE_COMPUTE_BIT, sizeof(glm::uvec4));
  pipeline_ = createComputePipeline(device, layout_, kCopyCompSpv, sizeof(kCopyCompSpv),
                                    gpu::kWorkgroupSize);

  const uint32_t perChunk = particlesPerChunk(context);
  const uint32_t chunks = (particles + perChunk - 1) / perChunk;
  pool_ = createStoragePool(device, chunks, 2 * chunks);
  for (uint32_t first = 0; first < particles; first += perChunk) {
    const uint32_t count = std::min(perChunk, particles - first);
    const VkDescriptorSet set = allocateSet(device, pool_, setLayout_);
    writeStorage(device, set, 0,
                 {source.get(), first * sizeof(Particle), count * sizeof(Particle)});
    writeStorage(device, set, 1,
                 {destination.get(), first * sizeof(Particle), count * sizeof(Particle)});
    sets_.emplace_back(set, count);
  }
}

void CopyKernel::record(VkCommandBuffer commands) const {
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  for (const auto& [set, count] : sets_) {
    const glm::uvec4 chunk{0u, count, 0u, 0u};
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0,
                            nullptr);
    vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(chunk), &chunk);
    vkCmdDispatch(commands, (count + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1, 1);
  }
}

double gpuCopySeconds(Context& context, uint32_t particles, int passes) {
  const VkDeviceSize bytes = VkDeviceSize{particles} * sizeof(Particle);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  Buffer source(context, bytes, usage, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  Buffer destination(context, bytes, usage, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  const CopyKernel copy(context, source, destination, particles);
  const TimestampPair timer(context);
  std::vector<double> times;
  for (int pass = -1; pass < passes; ++pass) {  // pass -1 warms up
    context.submitNow([&](VkCommandBuffer commands) {
      // WAW: the previous pass wrote the destination this one overwrites.
      memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
      timer.recordStart(commands);
      copy.record(commands);
      timer.recordEnd(commands);
    });
    if (pass >= 0) times.push_back(timer.seconds());
  }
  return median(times);
}

double cpuCopySeconds(uint32_t particles, unsigned threads, int passes) {
  std::vector<Particle> source(particles, Particle{{1, 2, 3, 4}, {5, 6, 7, 8}});
  std::vector<Particle> destination(particles);
  std::vector<double> times;
  for (int pass = -1; pass < passes; ++pass) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> workers;
    for (unsigned t = 0; t < threads; ++t)
      workers.emplace_back([&, t] {
        const size_t begin = size_t{particles} * t / threads;
        const size_t end = size_t{particles} * (t + 1) / threads;
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
