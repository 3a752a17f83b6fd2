// `lava info`: the Vulkan devices, the one Lava would pick, and the limits that bound a scene.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <thread>

#include "commands.h"
#include "lava/lava.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

class InfoCommand final : public Command {
 public:
  explicit InfoCommand(CLI::App& app)
      : Command(app, "info", "list Vulkan devices and the limits that matter"),
        options_(*command_) {
    options_.addInteger("device", "device index to describe [best; or LAVA_DEVICE]", device_, 0,
                        255);
  }

  int run() override {
    options_.resolve();
    Device device(deviceOptions(device_));
    std::printf("Vulkan devices:\n");
    for (const DeviceSummary& d : device.candidates()) {
      const uint32_t api = d.apiVersion;
      std::printf("  [%u] %-40s %-15s Vulkan %u.%u.%u%s\n", d.index, d.name.c_str(),
                  deviceTypeName(d.type), VK_API_VERSION_MAJOR(api), VK_API_VERSION_MINOR(api),
                  VK_API_VERSION_PATCH(api), d.index == device.index() ? "  <- selected" : "");
    }
    const VkPhysicalDeviceLimits& l = device.limits();
    const uint64_t mib = 1u << 20;
    std::printf("selected device %u: %s\n", device.index(), device.properties().deviceName);
    std::printf("  driver                          %s\n", device.driver().c_str());
    std::printf("  float controls                  %s\n", device.floatControls().c_str());
    std::printf("  optional paths                  %s\n", device.optionalPaths().c_str());
    std::printf("  64-bit buffer atomics           %s\n",
                device.handles().int64Atomics ? "yes (the splat adds two pixels per atomic)"
                                              : "no (the splat adds one pixel per atomic)");
    std::printf("  maxStorageBufferRange           %u bytes\n", l.maxStorageBufferRange);
    std::printf("  maxTexelBufferElements          %u\n", l.maxTexelBufferElements);
    std::printf("  maxComputeWorkGroupCount[0]     %u\n", l.maxComputeWorkGroupCount[0]);
    std::printf("  maxComputeWorkGroupInvocations  %u\n", l.maxComputeWorkGroupInvocations);
    std::printf("  maxPushConstantsSize            %u bytes\n", l.maxPushConstantsSize);
    std::printf("  maxImageDimension2D             %u\n", l.maxImageDimension2D);
    std::printf("  timestampPeriod                 %g ns\n", double(l.timestampPeriod));
    std::printf("  largest allocation              %llu MiB\n",
                static_cast<unsigned long long>(device.maxAllocationBytes() / mib));
    std::printf("  device-local memory             %llu MiB\n",
                static_cast<unsigned long long>(device.deviceLocalBytes() / mib));
    std::printf("  particles per chunk             %u (%zu bytes each; a buffer each)\n",
                device.particlesPerChunk(), sizeof(Particle));
    std::printf("  largest particle count          %llu\n",
                static_cast<unsigned long long>(device.maxParticles()));
    std::string targets;
    for (const std::string& t : cpuSimdTargets()) targets += (targets.empty() ? "" : ", ") + t;
    std::printf("host CPU: %u threads; cpu-simd runs %s (it can run %s)\n",
                std::max(1u, std::thread::hardware_concurrency()), cpuSimdTarget().c_str(),
                targets.c_str());
    return finish(device, 0);
  }

 private:
  Options options_;
  std::optional<unsigned> device_;
};

}  // namespace

std::unique_ptr<Command> makeInfo(CLI::App& app) {
  return std::make_unique<InfoCommand>(app);
}

}  // namespace lava::app
