// Presents through X11 MIT-SHM, for CPU Vulkan devices (lavapipe). Mesa 22's software WSI
// sends every frame through the X socket as one PutImage request when the server has no
// DRI3 (Xvfb, Xvnc, ...): at 1280x720 the server's and the client's share of that copy
// costs more CPU than drawing 262,144 lines. Here each frame slot
// has a System V shared-memory XImage the server reads in place, and renders straight into
// it: a linear color image over that memory (VK_EXT_external_memory_host). Where the
// device cannot, the slot renders offscreen, reads the frame back and copies it there.
//
// A frame is put on screen right after the next one was submitted, so the CPU copies one
// frame while the device draws the next; presentation lags one frame behind submission.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/offscreen.h"
#include "lava/device.h"
#include "presenter.h"

struct GLFWwindow;

namespace lava::window {

// MIT-SHM presentation is not possible for this window; what() says why.
class ShmUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ShmPresenter final : public Presenter {
 public:
  // The frames' color format: the byte order of a 24-bit TrueColor X visual.
  static constexpr VkFormat kFormat = VK_FORMAT_B8G8R8A8_UNORM;

  // Throws ShmUnavailable when the window is not on X11, the server lacks MIT-SHM or is
  // remote (it cannot attach our segment), or the window's visual is not 32-bit BGRX.
  ShmPresenter(const Device& device, GLFWwindow* window, uint32_t slots);
  // Whether the constructor would succeed for this window; if not, why (in `why`).
  static bool available(GLFWwindow* window, std::string* why);
  ~ShmPresenter() override;
  ShmPresenter(const ShmPresenter&) = delete;
  ShmPresenter& operator=(const ShmPresenter&) = delete;

  const char* name() const override { return "MIT-SHM"; }
  uint32_t imageCount() const override { return static_cast<uint32_t>(slots_.size()); }
  bool resize(VkExtent2D framebufferSize) override;
  VkExtent2D extent() const override { return extent_; }
  host::FrameTarget acquire(uint32_t slot) override;
  void recordAfterFrame(VkCommandBuffer commands, uint32_t slot) override;
  bool submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) override;
  void flush() override;

  struct X11;      // the display, window and GC (Xlib types stay out of this header)
  struct Segment;  // one slot's shared-memory XImage

 private:
  struct Slot {  // the segment first: the target's color image may live in its memory
    std::unique_ptr<Segment> segment;
    std::unique_ptr<host::OffscreenTarget> target;  // in the segment itself where possible
    bool drawn = false;  // a frame was submitted into it (so it holds one once acquired again)
  };
  void put(uint32_t slot);

  const Device& device_;
  std::unique_ptr<X11> x11_;
  std::vector<Slot> slots_;
  VkExtent2D extent_{0, 0};
  bool pending_ = false;  // a submitted frame is not on screen yet
  uint32_t pendingSlot_ = 0;
  VkFence pendingDone_ = VK_NULL_HANDLE;
};

}  // namespace lava::window
