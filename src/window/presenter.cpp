#include "presenter.h"

#include "host/output.h"

namespace lava::window {

PresentPath parsePresentPath(const std::string& source, const std::string& text) {
  if (text == "swapchain") return PresentPath::Swapchain;
  if (text == "shm") return PresentPath::Shm;
  throw InvalidArgument(source, "expected swapchain or shm, got '" + text + "'");
}

}  // namespace lava::window
