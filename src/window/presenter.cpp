#include "presenter.h"

#include "vk_check.h"

namespace lava {

PresentPath parsePresentPath(const std::string& source, const std::string& text) {
  if (text == "swapchain") return PresentPath::Swapchain;
  if (text == "shm") return PresentPath::Shm;
  throw UsageError(source + ": expected swapchain or shm, got '" + text + "'");
}

}  // namespace lava
