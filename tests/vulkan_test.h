// A fixture for tests that touch Vulkan: a device with the validation layer and its
// synchronization validation on; any message the layer reports fails the test. And a check
// the renderers' tests share: the cached backdrop.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "host/vulkan.h"
#include "lava/device.h"

namespace lava::test {

// LAVA_DEVICE_PROFILE=minimal runs every test on the fallback paths (ctest's *.Minimal).
inline DeviceOptions validatedOptions() {
  DeviceOptions options;
  options.validation = true;
  options.deviceExtensions = {VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME};
  const char* profile = std::getenv("LAVA_DEVICE_PROFILE");
  if (profile && !host::applyDeviceProfile(options, profile))
    throw std::invalid_argument(std::string("LAVA_DEVICE_PROFILE: expected ") +
                                host::kDeviceProfiles);
  return options;
}

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override { device_ = std::make_unique<Device>(validatedOptions()); }
  void TearDown() override {
    for (const std::string& message : device_->takeValidationMessages())
      ADD_FAILURE() << "validation: " << message;
  }
  Device& device() { return *device_; }

 private:
  std::unique_ptr<Device> device_;
};

// The frame `renderer` draws of `simulation` into `target`, its backdrop drawn anew, once a
// second frame into a fresh target of the same size was expected to copy the cached
// backdrop and to look exactly the same.
inline std::vector<uint8_t> expectTheBackdropCached(const Device& device,
                                                    host::FrameRenderer& renderer,
                                                    const GpuSimulation& simulation,
                                                    const host::OffscreenTarget& target,
                                                    const OrbitCamera& camera) {
  const auto drawn = host::renderOffscreen(device, renderer, simulation, target, camera);
  EXPECT_FALSE(renderer.backdropReused());
  // A fresh target: its colour must come from the copy, the depth tested against from the
  // cache.
  const host::OffscreenTarget fresh(device, target.extent());
  const auto copied = host::renderOffscreen(device, renderer, simulation, fresh, camera);
  EXPECT_TRUE(renderer.backdropReused());
  EXPECT_EQ(drawn, copied);
  return drawn;
}

}  // namespace lava::test
