// Turns every failing VkResult into an exception naming the call, the result and file:line,
// in every build type.
#pragma once
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace lava {

const char* resultName(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const char* call, const char* file, int line);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

// Bad input from the user (exit status 2): the message names the flag and accepted range.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A resource (memory, device) ran out or is missing (exit status 1).
class ResourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace lava

#define VK_CHECK(call)                                                   \
  do {                                                                   \
    VkResult lavaResult_ = (call);                                       \
    if (lavaResult_ != VK_SUCCESS)                                       \
      throw ::lava::VulkanError(lavaResult_, #call, __FILE__, __LINE__); \
  } while (0)
