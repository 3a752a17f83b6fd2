#include "shm_presenter.h"

#include <dlfcn.h>
#include <sys/ipc.h>
#include <sys/shm.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

#include "host/output.h"

// Xlib last: its macros (None, Bool, Status, ...) must not reach the headers above.
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XShm.h>

namespace lava::window {
namespace {

// GLFW's X11 handles, looked up at run time: Debian's GLFW may be its Wayland build, which
// lacks these functions, and the binary must still start there (and use the swapchain).
struct GlfwX11 {
  Display* display = nullptr;
  Window window = 0;
};

GlfwX11 glfwX11(GLFWwindow* window) {
  using GetDisplay = Display* (*)();
  using GetWindow = Window (*)(GLFWwindow*);
  auto getDisplay = reinterpret_cast<GetDisplay>(dlsym(RTLD_DEFAULT, "glfwGetX11Display"));
  auto getWindow = reinterpret_cast<GetWindow>(dlsym(RTLD_DEFAULT, "glfwGetX11Window"));
  if (!getDisplay || !getWindow) return {};
  return {getDisplay(), getWindow(window)};
}

// Xlib reports protocol errors asynchronously to a process-wide handler whose default
// exits; an ErrorTrap catches those of the requests made during its lifetime.
int trappedError = 0;
int recordError(Display*, XErrorEvent* event) {
  trappedError = event->error_code;
  return 0;
}

class ErrorTrap {
 public:
  explicit ErrorTrap(Display* display) : display_(display) {
    XSync(display_, False);
    trappedError = 0;
    previous_ = XSetErrorHandler(recordError);
  }
  ~ErrorTrap() { XSetErrorHandler(previous_); }
  // The first error code since the trap was set, once the server processed every request.
  int error() const {
    XSync(display_, False);
    return trappedError;
  }

 private:
  Display* display_;
  int (*previous_)(Display*, XErrorEvent*);
};

}  // namespace

struct ShmPresenter::X11 {
  Display* display = nullptr;
  Window window = 0;
  Visual* visual = nullptr;
  int depth = 0;
  GC gc = nullptr;
  ~X11() {
    if (gc) XFreeGC(display, gc);
  }
};

// A shared-memory XImage the server has attached. Marked for removal at once, so the
// segment disappears with the process even if it dies.
struct ShmPresenter::Segment {
  Display* display;
  XImage* image = nullptr;
  XShmSegmentInfo info{};
  bool attached = false;
  bool putPending = false;  // the server may still be reading it

  // `atLeast`: bytes the segment must hold beyond the image (to import it as device memory).
  Segment(const X11& x11, VkExtent2D extent, size_t atLeast = 0) : display(x11.display) {
    try {
      create(x11, extent, atLeast);
    } catch (...) {
      release();
      throw;
    }
  }
  ~Segment() { release(); }

 private:
  void create(const X11& x11, VkExtent2D extent, size_t atLeast) {
    image = XShmCreateImage(display, x11.visual, unsigned(x11.depth), ZPixmap, nullptr, &info,
                            extent.width, extent.height);
    if (!image) throw ShmUnavailable("XShmCreateImage failed");
    if (image->bits_per_pixel != 32) throw ShmUnavailable("the window's pixels are not 32-bit");
    const size_t bytes = std::max(size_t(image->bytes_per_line) * extent.height, atLeast);
    info.shmid = shmget(IPC_PRIVATE, bytes, IPC_CREAT | 0600);
    if (info.shmid < 0)
      throw ResourceError("shmget of " + std::to_string(bytes) +
                          " bytes failed: " + std::strerror(errno));
    void* address = shmat(info.shmid, nullptr, 0);
    shmctl(info.shmid, IPC_RMID, nullptr);
    if (address == reinterpret_cast<void*>(-1))
      throw ResourceError(std::string("shmat failed: ") + std::strerror(errno));
    info.shmaddr = image->data = static_cast<char*>(address);
    info.readOnly = False;
    ErrorTrap trap(display);
    attached = XShmAttach(display, &info);
    if (!attached || trap.error() != 0) {
      attached = false;
      throw ShmUnavailable("the X server cannot attach shared memory (a remote display?)");
    }
  }

  void release() {
    if (attached) {
      XShmDetach(display, &info);
      XSync(display, False);
      attached = false;
    }
    if (info.shmaddr) shmdt(info.shmaddr);
    info.shmaddr = nullptr;
    if (image) {
      image->data = nullptr;  // not malloc'd: XDestroyImage must not free it
      XDestroyImage(image);
      image = nullptr;
    }
  }
};

namespace {

// The window's display and visual, checked for what put() relies on (throws ShmUnavailable).
void openX11(GLFWwindow* window, ShmPresenter::X11& x11) {
  const GlfwX11 handles = glfwX11(window);
  if (!handles.display || !handles.window) throw ShmUnavailable("the window is not on X11");
  x11.display = handles.display;
  x11.window = handles.window;
  if (!XShmQueryExtension(x11.display)) throw ShmUnavailable("the X server has no MIT-SHM");
  XWindowAttributes attributes;
  if (!XGetWindowAttributes(x11.display, x11.window, &attributes))
    throw ShmUnavailable("cannot read the window's attributes");
  const Visual* visual = attributes.visual;
  if (visual->c_class != TrueColor || visual->red_mask != 0xff0000 ||
      visual->green_mask != 0xff00 || visual->blue_mask != 0xff ||
      ImageByteOrder(x11.display) != LSBFirst)
    throw ShmUnavailable("the window's visual is not BGRX TrueColor");
  x11.visual = attributes.visual;
  x11.depth = attributes.depth;
  ShmPresenter::Segment probe(x11, {1, 1});  // a remote server fails here
}

}  // namespace

bool ShmPresenter::available(GLFWwindow* window, std::string* why) {
  try {
    X11 x11;
    openX11(window, x11);
    return true;
  } catch (const ShmUnavailable& e) {
    if (why) *why = e.what();
    return false;
  }
}

ShmPresenter::ShmPresenter(const Device& device, GLFWwindow* window, uint32_t slots)
    : device_(device), x11_(std::make_unique<X11>()), slots_(slots) {
  openX11(window, *x11_);
  x11_->gc = XCreateGC(x11_->display, x11_->window, 0, nullptr);
}

ShmPresenter::~ShmPresenter() {
  vkDeviceWaitIdle(device_.handles().device);
  slots_.clear();
}

bool ShmPresenter::resize(VkExtent2D framebufferSize) {
  VK_CHECK(vkDeviceWaitIdle(device_.handles().device));
  pending_ = false;  // drawn for the old size: dropped
  for (Slot& slot : slots_) {
    slot.target.reset();  // its color image may live in the segment's memory
    slot.segment.reset();
    slot.drawn = false;
  }
  extent_ = {0, 0};
  if (framebufferSize.width == 0 || framebufferSize.height == 0) return false;
  // The pass renders straight into the segment when the device can use host memory for a
  // packed linear image; else the frame is read back and put() copies it there.
  const VkDeviceSize alignment =
      std::max<VkDeviceSize>(host::OffscreenTarget::hostImportAlignment(device_), 1);
  std::optional<VkDeviceSize> hostBytes;
  if (host::OffscreenTarget::hostColorSupported(device_, kFormat))
    hostBytes = host::OffscreenTarget::hostBytes(device_, framebufferSize, kFormat);
  for (Slot& slot : slots_) {
    slot.segment = std::make_unique<Segment>(*x11_, framebufferSize, hostBytes.value_or(0));
    const XImage* image = slot.segment->image;
    const bool inPlace = hostBytes &&
                         size_t(image->bytes_per_line) == size_t(framebufferSize.width) * 4 &&
                         reinterpret_cast<uintptr_t>(image->data) % alignment == 0;
    if (inPlace) {
      try {
        slot.target = std::make_unique<host::OffscreenTarget>(device_, framebufferSize, kFormat,
                                                              static_cast<void*>(image->data));
      } catch (const lava::Error&) {
        // The driver refused this memory after all: read the frames back instead.
      }
    }
    if (!slot.target)
      slot.target = std::make_unique<host::OffscreenTarget>(device_, framebufferSize, kFormat);
  }
  extent_ = framebufferSize;
  return true;
}

host::FrameTarget ShmPresenter::acquire(uint32_t slot) {
  if (!slots_[slot].target) return {};
  if (slots_[slot].segment->putPending) {  // the server must be done reading it before it is
    XSync(x11_->display, False);           // written again (by the pass or by put())
    for (Slot& s : slots_) s.segment->putPending = false;
  }
  // The slot's previous frame has finished: where it was drawn in place, the renderer may
  // write the next one's backdrop from the host.
  const Slot& s = slots_[slot];
  return s.drawn && s.target->inHostMemory() ? s.target->targetWithHostColor() : s.target->target();
}

void ShmPresenter::recordAfterFrame(VkCommandBuffer commands, uint32_t slot) {
  slots_[slot].target->recordReadback(commands);
}

bool ShmPresenter::submitAndPresent(VkCommandBuffer commands, VkFence done, uint32_t slot) {
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  VK_CHECK(vkQueueSubmit(device_.handles().queue, 1, &submit, done));
  slots_[slot].drawn = true;
  flush();  // the previous frame, while the device works on this one
  pending_ = true;
  pendingSlot_ = slot;
  pendingDone_ = done;
  return true;
}

void ShmPresenter::flush() {
  if (!pending_) return;
  pending_ = false;
  if (const VkResult waited =
          vkWaitForFences(device_.handles().device, 1, &pendingDone_, VK_TRUE, UINT64_MAX);
      waited != VK_SUCCESS) {
    vkDeviceWaitIdle(device_.handles().device);  // the frame may still run
    throw VulkanError(waited, "vkWaitForFences", __FILE__, __LINE__);
  }
  put(pendingSlot_);
}

void ShmPresenter::put(uint32_t index) {
  Slot& slot = slots_[index];
  Segment& segment = *slot.segment;
  const size_t row = size_t(extent_.width) * 4;
  const uint8_t* source = slot.target->mappedPixels();
  XImage* image = segment.image;
  if (slot.target->inHostMemory()) {
    // The pass drew into the segment itself.
  } else {
    host::copyRows(reinterpret_cast<uint8_t*>(image->data), size_t(image->bytes_per_line), source,
                   row, extent_.height);
  }
  XShmPutImage(x11_->display, x11_->window, x11_->gc, image, 0, 0, 0, 0, extent_.width,
               extent_.height, False);
  XFlush(x11_->display);
  segment.putPending = true;
}

}  // namespace lava::window
