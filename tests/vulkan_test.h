// A fixture for tests that touch Vulkan: a device with the validation layer and its
// synchronization validation on; any message the layer reports fails the test.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

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

}  // namespace lava::test
