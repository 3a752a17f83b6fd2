// Where the demo's frames go: a Vulkan swapchain (Swapchain), or, for a CPU device on X11,
// shared memory the X server reads (ShmPresenter). The demo records the same frame for
// both; a slot is one of its frames in flight, and a slot's previous commands have finished
// (its fence was waited on) before the demo asks for that slot again.
#pragma once
#include <vulkan/vulkan.h>

#include <optional>
#include <string>

#include "host/offscreen.h"

namespace lava::window {

// How `lava demo` presents (--present).
enum class PresentPath { Swapchain, Shm };

// Parses "swapchain" or "shm" for the flag named by `source` (lava::InvalidArgument otherwise).
PresentPath parsePresentPath(const std::string& source, const std::string& text);

class Presenter {
 public:
  virtual ~Presenter() = default;

  // For the summary line: "mailbox", "fifo (vsync)", "MIT-SHM", ...
  virtual const char* name() const = 0;
  // How many images the targets cycle through (Dear ImGui sizes its buffers by it).
  virtual uint32_t imageCount() const = 0;

  // Rebuilds the targets for the window's framebuffer size; false while it is 0x0
  // (minimised). Waits for the device to be idle first.
  virtual bool resize(VkExtent2D framebufferSize) = 0;
  virtual VkExtent2D extent() const = 0;

  // The target of `slot`'s next frame, once the slot's previous frame has finished; its
  // color image is VK_NULL_HANDLE when the targets are out of date (resize, then try again).
  virtual host::FrameTarget acquire(uint32_t slot) = 0;
  // Records what must follow the frame in its command buffer.
  virtual void recordAfterFrame(VkCommandBuffer commands, uint32_t slot) = 0;
  // Submits the frame (signalling `done` when it finished) and presents it; false when the
  // targets went out of date on the way.
  virtual bool submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) = 0;
  // Presents any frame still held back (before the window closes).
  virtual void flush() {}
};

}  // namespace lava::window
