// The validation harness itself: a barrier removed on purpose must be reported, or the
// "validation-clean" claims of every other test would mean nothing.
#include <gtest/gtest.h>

#include "descriptors.h"
#include "roofline.h"
#include "shared.h"
#include "vulkan_test.h"

namespace lava {
namespace {

class Harness : public ::testing::Test {
 protected:
  Context context_{test::validatedOptions()};
};

// Copies a -> b, then b -> c: the second pass reads what the first wrote (RAW on b).
std::vector<std::string> copyTwice(Context& context, bool withBarrier) {
  const uint32_t particles = 4096;
  const VkDeviceSize bytes = particles * sizeof(gpu::Particle);
  Buffer a(context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  Buffer b(context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  Buffer c(context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  const CopyKernel first(context, a, b, particles), second(context, b, c, particles);
  context.submitNow([&](VkCommandBuffer commands) {
    first.record(commands);
    if (withBarrier) {
      // RAW: the first copy writes b, the second reads it.
      memoryBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    }
    second.record(commands);
  });
  return context.takeValidationMessages();
}

TEST_F(Harness, MissingBarrierIsReportedBySynchronizationValidation) {
  const std::vector<std::string> messages = copyTwice(context_, false);
  ASSERT_FALSE(messages.empty()) << "synchronization validation missed a RAW hazard";
  bool raw = false;
  for (const std::string& m : messages)
    raw = raw || m.find("READ_AFTER_WRITE") != std::string::npos;
  EXPECT_TRUE(raw) << messages.front();
}

TEST_F(Harness, TheSameWorkWithItsBarrierIsClean) {
  const std::vector<std::string> messages = copyTwice(context_, true);
  EXPECT_TRUE(messages.empty()) << messages.front();
}

TEST_F(Harness, AnInvalidCallIsReportedByCoreValidation) {
  // A zero-size buffer breaks VUID-VkBufferCreateInfo-size-00912; the driver may accept it.
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  if (vkCreateBuffer(context_.device(), &info, nullptr, &buffer) == VK_SUCCESS && buffer)
    vkDestroyBuffer(context_.device(), buffer, nullptr);
  const std::vector<std::string> messages = context_.takeValidationMessages();
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages.front().find("VUID-VkBufferCreateInfo-size"), std::string::npos)
      << messages.front();
}

}  // namespace
}  // namespace lava
