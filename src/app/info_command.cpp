// `lava info`: the Vulkan devices, the one Lava would pick, and the limits that bound a scene.
#include <cstdio>
#include <optional>

#include "commands.h"
#include "gpu_simulator.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

class InfoCommand final : public Command {
 public:
  explicit InfoCommand(CLI::App& app)
      : Command(app.add_subcommand("info", "list Vulkan devices and the limits that matter")),
        options_(*command_) {
    options_.add("device", Kind::Number, "device index to describe [best; or LAVA_DEVICE]",
                 [this](const std::string& src, const std::string& t) {
                   device_ = static_cast<unsigned>(parseInteger(src, t, 0, 255));
                 });
  }

  int run() override {
    options_.resolve();
    Context context(contextOptions(device_));
    std::printf("Vulkan devices:\n");
    for (const DeviceSummary& d : context.devices()) {
      const uint32_t api = d.properties.apiVersion;
      std::printf("  [%u] %-40s %-15s Vulkan %u.%u.%u%s\n", d.index, d.name.c_str(),
                  deviceTypeName(d.type), VK_API_VERSION_MAJOR(api), VK_API_VERSION_MINOR(api),
                  VK_API_VERSION_PATCH(api),
                  d.index == context.deviceIndex() ? "  <- selected" : "");
    }
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &driver;
    vkGetPhysicalDeviceProperties2(context.physicalDevice(), &properties);
    const VkPhysicalDeviceLimits& l = context.limits();
    const uint64_t mib = 1u << 20;
    std::printf("selected device %u: %s\n", context.deviceIndex(), context.properties().deviceName);
    std::printf("  driver                          %s %s\n", driver.driverName, driver.driverInfo);
    std::printf("  maxStorageBufferRange           %u bytes\n", l.maxStorageBufferRange);
    std::printf("  maxComputeWorkGroupCount[0]     %u\n", l.maxComputeWorkGroupCount[0]);
    std::printf("  maxComputeWorkGroupInvocations  %u\n", l.maxComputeWorkGroupInvocations);
    std::printf("  maxPushConstantsSize            %u bytes\n", l.maxPushConstantsSize);
    std::printf("  maxImageDimension2D             %u\n", l.maxImageDimension2D);
    std::printf("  timestampPeriod                 %g ns\n", double(l.timestampPeriod));
    std::printf("  largest allocation              %llu MiB\n",
                static_cast<unsigned long long>(context.maxAllocationSize() / mib));
    std::printf("  device-local memory             %llu MiB\n",
                static_cast<unsigned long long>(context.deviceMemory() / mib));
    std::printf("  particles per chunk             %u (%zu bytes each; a buffer each)\n",
                particlesPerChunk(context), sizeof(Particle));
    std::printf("  largest particle count          %llu\n",
                static_cast<unsigned long long>(maxParticles(context)));
    return finish(context, 0);
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
