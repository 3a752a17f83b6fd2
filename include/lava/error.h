// What Lava throws. Every error derives from lava::Error; messages name the parameter (a
// scene key such as "rate" or "emitter[1].radius") or the Vulkan call, never a program's
// command-line flag.
#pragma once
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

#include "export.h"

namespace lava {

class LAVA_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A value the caller passed is malformed, out of range or inconsistent. what() is
// "<parameter>: <detail>"; detail() says what is accepted and what was given.
class LAVA_API InvalidArgument : public Error {
 public:
  InvalidArgument(std::string parameter, std::string detail);
  const std::string& parameter() const { return parameter_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string parameter_;
  std::string detail_;
};

// The device ran out of memory, or lacks a feature or an extension Lava needs.
class LAVA_API ResourceError : public Error {
 public:
  using Error::Error;
};

// A Vulkan call returned an error: what() names the call, the result and where.
class LAVA_API VulkanError : public Error {
 public:
  VulkanError(VkResult result, const std::string& call, const char* file, int line);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

// "VK_ERROR_DEVICE_LOST" for VK_ERROR_DEVICE_LOST, and so on; "VkResult -1000012000" for a
// value it does not list.
LAVA_API std::string resultName(VkResult result);

}  // namespace lava
