// The validation harness itself: a barrier removed on purpose must be reported, or the
// "validation-clean" claims of every other test would mean nothing.
#include <gtest/gtest.h>

#include "lava/device.h"
#include "lava/error.h"
#include "lava/state.h"
#include "vulkan/buffer.h"
#include "vulkan/commands.h"
#include "vulkan_test.h"

namespace lava {
namespace {

class Harness : public ::testing::Test {
 protected:
  Device device_{test::validatedOptions()};
};

// Copies a -> b, then b -> c: the second copy reads what the first wrote (RAW on b).
std::vector<std::string> copyTwice(Device& device, bool withBarrier) {
  const detail::DeviceContext& c = device.context();
  const VkDeviceSize bytes = 4096 * sizeof(Particle);
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const detail::Buffer a(c, bytes, usage, detail::MemoryUse::Device);
  const detail::Buffer b(c, bytes, usage, detail::MemoryUse::Device);
  const detail::Buffer d(c, bytes, usage, detail::MemoryUse::Device);
  c.submitNow([&](VkCommandBuffer commands) {
    const VkBufferCopy region{0, 0, bytes};
    c.vk.CmdCopyBuffer(commands, a.get(), b.get(), 1, &region);
    if (withBarrier) {
      // RAW: the first copy writes b, the second reads it.
      detail::memoryBarrier(c, commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_TRANSFER_READ_BIT);
    }
    c.vk.CmdCopyBuffer(commands, b.get(), d.get(), 1, &region);
  });
  return device.takeValidationMessages();
}

TEST_F(Harness, MissingBarrierIsReportedBySynchronizationValidation) {
  const std::vector<std::string> messages = copyTwice(device_, false);
  ASSERT_FALSE(messages.empty()) << "synchronization validation missed a RAW hazard";
  bool raw = false;
  for (const std::string& m : messages)
    raw = raw || m.find("READ_AFTER_WRITE") != std::string::npos;
  EXPECT_TRUE(raw) << messages.front();
}

TEST_F(Harness, TheSameWorkWithItsBarrierIsClean) {
  const std::vector<std::string> messages = copyTwice(device_, true);
  EXPECT_TRUE(messages.empty()) << messages.front();
}

TEST_F(Harness, AnInvalidCallIsReportedByCoreValidation) {
  // A zero-size buffer breaks VUID-VkBufferCreateInfo-size-00912; the driver may accept it.
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDevice device = device_.handles().device;
  if (vkCreateBuffer(device, &info, nullptr, &buffer) == VK_SUCCESS && buffer)
    vkDestroyBuffer(device, buffer, nullptr);
  const std::vector<std::string> messages = device_.takeValidationMessages();
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages.front().find("VUID-VkBufferCreateInfo-size"), std::string::npos)
      << messages.front();
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

// The small promises of the internals the rest is built on.
TEST_F(Harness, AMovedBufferLeavesItsSourceEmpty) {
  const detail::DeviceContext& c = device_.context();
  detail::Buffer upload(c, 256, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, detail::MemoryUse::Upload);
  void* mapped = upload.mapped();
  ASSERT_NE(mapped, nullptr);
  detail::Buffer moved(std::move(upload));
  EXPECT_EQ(moved.mapped(), mapped);
  EXPECT_EQ(upload.mapped(), nullptr);  // NOLINT(bugprone-use-after-move): what is tested
  EXPECT_EQ(upload.get(), VK_NULL_HANDLE);
  EXPECT_EQ(upload.size(), 0u);
  detail::Buffer assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.mapped(), mapped);
  EXPECT_EQ(moved.mapped(), nullptr);  // NOLINT(bugprone-use-after-move)
}

TEST(Errors, AnUnlistedResultKeepsItsNumber) {
  EXPECT_EQ(resultName(VK_ERROR_DEVICE_LOST), "VK_ERROR_DEVICE_LOST");
  EXPECT_EQ(resultName(VK_ERROR_UNKNOWN), "VK_ERROR_UNKNOWN");
  EXPECT_EQ(resultName(static_cast<VkResult>(-1000012345)), "VkResult -1000012345");
  const VulkanError error(static_cast<VkResult>(-1000012345), "vkQueueSubmit", "x.cpp", 7);
  EXPECT_NE(std::string(error.what()).find("-1000012345"), std::string::npos) << error.what();
}

}  // namespace
}  // namespace lava
