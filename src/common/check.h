// VK_CHECK: every failing VkResult becomes a lava::VulkanError naming the call, the result
// and file:line, in every build type.
#pragma once
#include "lava/error.h"

#define VK_CHECK(call)                                                   \
  do {                                                                   \
    const VkResult lavaResult_ = (call);                                 \
    if (lavaResult_ != VK_SUCCESS)                                       \
      throw ::lava::VulkanError(lavaResult_, #call, __FILE__, __LINE__); \
  } while (0)

// The same for a result already in hand, naming the call that returned it.
#define VK_CHECK_RESULT(result, name)                                   \
  do {                                                                 \
    const VkResult lavaResult_ = (result);                             \
    if (lavaResult_ != VK_SUCCESS)                                     \
      throw ::lava::VulkanError(lavaResult_, name, __FILE__, __LINE__); \
  } while (0)
