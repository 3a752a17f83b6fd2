#include "demo_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <utility>

#include "common/steps.h"
#include "demo_input.h"
#include "demo_panel.h"
#include "frame_timer.h"
#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "host/output.h"
#include "lava/lava.h"
#include "shm_presenter.h"
#include "swapchain.h"
#include "ui.h"

namespace lava::window {
namespace {

constexpr uint32_t kFramesInFlight = 2;
constexpr uint32_t kStepsPerFrameMax = 2048;

std::string glfwError() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

struct GlfwSession {
  GlfwSession() {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland))
      throw NoDisplay("no display (DISPLAY and WAYLAND_DISPLAY are not set)");
    if (!glfwInit()) throw NoDisplay("no display (" + glfwError() + ")");
    if (!glfwVulkanSupported()) {
      glfwTerminate();
      throw NoDisplay("no Vulkan window support (GLFW found no Vulkan loader)");
    }
  }
  ~GlfwSession() { glfwTerminate(); }
};

struct GlfwWindow {
  GLFWwindow* handle;
  explicit GlfwWindow(VkExtent2D size) {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    handle = glfwCreateWindow(int(size.width), int(size.height), "Lava", nullptr, nullptr);
    if (!handle) throw NoDisplay("cannot open a window (" + glfwError() + ")");
  }
  ~GlfwWindow() { glfwDestroyWindow(handle); }
};

// The window's surface, created only for swapchain presentation.
struct Surface {
  VkInstance instance = VK_NULL_HANDLE;
  VkSurfaceKHR handle = VK_NULL_HANDLE;
  Surface() = default;
  Surface(VkInstance i, GLFWwindow* window) : instance(i) {
    VK_CHECK(glfwCreateWindowSurface(instance, window, nullptr, &handle));
  }
  Surface(const Surface&) = delete;
  Surface& operator=(Surface&& other) noexcept {
    std::swap(instance, other.instance);
    std::swap(handle, other.handle);
    return *this;
  }
  ~Surface() {
    if (handle) vkDestroySurfaceKHR(instance, handle, nullptr);
  }
};

DeviceOptions windowDeviceOptions(const DemoOptions& options) {
  uint32_t count = 0;
  const char** extensions = glfwGetRequiredInstanceExtensions(&count);
  if (!extensions) throw NoDisplay("no Vulkan surface extensions for this display");
  DeviceOptions device;
  device.instanceExtensions.assign(extensions, extensions + count);
  // Where offered: presentation, and MIT-SHM rendering into the X server's memory.
  device.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME,
                             VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME};
  device.validation = options.validation;
  device.index = options.device;
  device.framesInFlight = kFramesInFlight;
  return device;
}

struct FrameSlot {
  VkCommandBuffer commands = VK_NULL_HANDLE;
  host::OwnedFence inFlight;
};

// CPU time of this process, all its threads (the device's too on a CPU device), in s.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// --present, or when it is not given: MIT-SHM for a CPU device (lavapipe) on an X server
// that can attach our memory, unless vsync was asked for; the swapchain otherwise.
PresentPath choosePresentPath(const DemoOptions& options, const Device& device,
                              GLFWwindow* window) {
  std::string why;
  if (options.present == PresentPath::Shm && !ShmPresenter::available(window, &why))
    throw InvalidArgument("--present", "shm is not possible here (" + why + ")");
  if (options.present) return *options.present;
  if (options.vsync || device.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU)
    return PresentPath::Swapchain;
  return ShmPresenter::available(window, nullptr) ? PresentPath::Shm : PresentPath::Swapchain;
}

// The frames' color format for `path`. A window the driver cannot present to at all (a
// 16-bit X display: Mesa presents to depth 24 and 32 only) is no display for the demo.
VkSurfaceFormatKHR windowFormat(PresentPath path, const Device& device, VkSurfaceKHR surface) {
  if (path == PresentPath::Shm) return {ShmPresenter::kFormat, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
  if (!device.hasExtension(VK_KHR_SWAPCHAIN_EXTENSION_NAME))
    throw NoDisplay("the device cannot present (no VK_KHR_swapchain)");
  const std::optional<VkSurfaceFormatKHR> format = Swapchain::chooseFormat(device, surface);
  if (!format)
    throw NoDisplay(
        "the window surface offers no formats (the driver presents to 24- and 32-bit X "
        "displays: run the X server at depth 24)");
  return *format;
}

class Demo {
 public:
  explicit Demo(const DemoOptions& options)
      : options_(options),
        scene_(options.scene),
        window_(options.size),
        device_(windowDeviceOptions(options)),
        path_(choosePresentPath(options, device_, window_.handle)),
        surface_(path_ == PresentPath::Swapchain
                     ? Surface(device_.handles().instance, window_.handle)
                     : Surface()),
        format_(windowFormat(path_, device_, surface_.handle)),
        simulation_(drawing(scene_)),
        renderer_(device_, format_.format, options.style),
        timer_(device_, kFramesInFlight) {
    if (path_ == PresentPath::Shm)
      presenter_ = std::make_unique<ShmPresenter>(device_, window_.handle, kFramesInFlight);
    else
      presenter_ = std::make_unique<Swapchain>(device_, surface_.handle, format_, options.vsync,
                                               kFramesInFlight);
    if (!presenter_->resize(framebufferSize())) throw NoDisplay("the window has no area");
    renderer_.setLineMode(options.lines);
    renderer_.setSettings(options.look);
    if (options.cpu) cpu_ = stepping(scene_);
    if (options.start) stepper().setState(*options.start);
    stepper().advance(scene_.stepsIn(options.warmup));
    showCpuState();
    simulatedSeconds_ = double(scene_.stepsIn(options.warmup)) * double(scene_.h());
    ui_ = std::make_unique<Ui>(device_, window_.handle, format_.format, presenter_->imageCount());
    createFrameSlots();
  }

  ~Demo() { vkDeviceWaitIdle(device_.handles().device); }

  DemoSummary run() {
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = processCpuSeconds();
    lastTimed_ = glfwGetTime();
    auto last = start;
    uint32_t presented = 0;
    while (!glfwWindowShouldClose(window_.handle)) {
      glfwPollEvents();
      const auto now = std::chrono::steady_clock::now();
      const double frameSeconds = std::chrono::duration<double>(now - last).count();
      last = now;
      const bool lastFrame = options_.frames != 0 && presented + 1 >= options_.frames;
      if (!drawFrame(frameSeconds, lastFrame)) {
        glfwWaitEventsTimeout(0.02);  // minimised: wait without spinning
        continue;
      }
      fps_ = fps_ * 0.9 + 0.1 / std::max(frameSeconds, 1e-6);
      ++presented;
      if (options_.frames && presented >= options_.frames) break;
    }
    presenter_->flush();
    device_.waitIdle();
    // The frames still in flight at the end, oldest first: their stamps count too.
    for (uint32_t k = 0; k < kFramesInFlight; ++k) readTimings((frame_ + k) % kFramesInFlight);
    DemoSummary summary;
    summary.frames = presented;
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.cpuSeconds = processCpuSeconds() - cpuStart;
    summary.size = presenter_->extent();
    summary.device = device_.properties().deviceName;
    summary.presentMode = presenter_->name();
    summary.simulateMs = simulateMs_;
    summary.drawMs = drawMs_;
    for (const std::string& m : device_.takeValidationMessages()) {
      std::fprintf(stderr, "lava: validation: %s\n", m.c_str());
      ++summary.validationMessages;
    }
    return summary;
  }

 private:
  VkExtent2D framebufferSize() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
  }

  static GpuSimulationOptions simulationOptions() {
    GpuSimulationOptions o;
    o.maxStepsPerFrame = kStepsPerFrameMax;
    return o;
  }

  // The device's simulation of `scene`: it steps it, or only draws what the CPU steps.
  std::unique_ptr<GpuSimulation> drawing(const Scene& scene) {
    return std::make_unique<GpuSimulation>(device_, options_.cpu ? host::drawnScene(scene) : scene,
                                           simulationOptions());
  }

  std::unique_ptr<CpuSimulation> stepping(const Scene& scene) const {
    return std::make_unique<CpuSimulation>(scene, options_.cpu->threads, options_.cpu->kernel);
  }

  // The simulation that steps the run, the one the panel edits.
  Simulation& stepper() { return cpu_ ? static_cast<Simulation&>(*cpu_) : *simulation_; }

  // The CPU's state to the device, which draws it (its own submission, ordered after the
  // frames in flight; GpuSimulation::setState).
  void showCpuState() {
    if (cpu_) simulation_->setState(host::drawnState(cpu_->view()));
  }

  // The panel, its edits to the simulation that steps; a live edit the CPU took goes to the
  // device's copy too, which draws it.
  void buildPanel() {
    const bool edited = panel_.build(device_.properties().deviceName,
                                     [this] { return figures(); }, controls_, renderer_,
                                     stepper(), scene_);
    if (edited && cpu_) simulation_->setScene(host::drawnScene(scene_));
  }

  void stepOnCpu(uint32_t steps) {
    const auto start = std::chrono::steady_clock::now();
    cpu_->advance(steps);
    showCpuState();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    cpuMs_ = cpuMs_ > 0.0 ? 0.8 * cpuMs_ + 0.2 * ms : ms;
  }

  void createFrameSlots() {
    VkDevice device = device_.handles().device;
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = device_.handles().queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateCommandPool(device, &poolInfo, nullptr, &pool));
    pool_ = host::OwnedCommandPool(device, pool);
    for (FrameSlot& slot : slots_) {
      VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
      alloc.commandPool = pool_;
      alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      alloc.commandBufferCount = 1;
      VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &slot.commands));
      VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      VkFence fence = VK_NULL_HANDLE;
      VK_CHECK(vkCreateFence(device, &fenceInfo, nullptr, &fence));
      slot.inFlight = host::OwnedFence(device, fence);
    }
  }

  // The GPU times smoothed over the timed frames (about ten a second), the first taken as is.
  void readTimings(uint32_t index) {
    if (const std::optional<FrameTimes> t = timer_.read(index)) {
      const double keep = timedFrames_++ ? 0.8 : 0.0;
      simulateMs_ = cpu_ ? cpuMs_ : simulateMs_ * keep + (1.0 - keep) * t->simulateMs;
      drawMs_ = drawMs_ * keep + (1.0 - keep) * t->drawMs;
    }
  }

  // Steps owed for this frame: a fixed h decoupled from the frame rate (at most 0.1 s of
  // simulated time per frame, so a stall does not snowball).
  uint32_t stepsFor(double frameSeconds) {
    if (std::exchange(controls_.stepOnce, false)) return 1;
    if (controls_.paused) return 0;
    const uint64_t steps =
        owed_.take(std::min(frameSeconds, 0.1) * controls_.speed / double(scene_.h()));
    return static_cast<uint32_t>(std::min<uint64_t>(steps, kStepsPerFrameMax));
  }

  // Slots born at least once (the clocks stay on the host: no read-back).
  uint64_t alive() const {
    uint64_t n = 0;
    for (size_t k = 0; k < scene_.emitters.size(); ++k)
      n += std::min<uint64_t>(simulation_->clocks()[k].serial, scene_.emitters[k].particles);
    return n;
  }

  // The panel's figures, now.
  DemoFigures figures() const {
    return {fps_, simulateMs_, drawMs_, simulatedSeconds_, alive()};
  }

  // Serves the controls' one-shot requests other than a step.
  void applyRequests() {
    if (controls_.restart || controls_.reset) startOver();
    if (std::exchange(controls_.screenshot, false)) saveScreenshot();
  }

  // R: the running scene from its initial state; the panel's restart: a new simulation of
  // the edited scene, or the running one kept with the reason shown.
  void startOver() {
    device_.waitIdle();
    if (controls_.restart) {
      try {
        const Scene next = panel_.edited();
        checkScene(next);
        if (next.particles() > device_.maxParticles())
          throw InvalidArgument(
              "particles", "this device holds at most " + std::to_string(device_.maxParticles()));
        simulation_.reset();
        simulation_ = drawing(next);
        if (cpu_) cpu_ = stepping(next);
        scene_ = next;
        panel_.setMessage("restarted");
      } catch (const Error& e) {
        panel_.setMessage(e.what());
        if (simulation_) {  // refused before it began: the running simulation goes on
          controls_.restart = controls_.reset = false;
          return;
        }
        simulation_ = drawing(scene_);
      }
    } else {
      stepper().setState(initialState(scene_));
    }
    showCpuState();
    simulatedSeconds_ = 0.0;
    controls_.restart = controls_.reset = false;
    owed_.reset();
  }

  // P: this frame as the window shows it, offscreen, into the next free numbered PNG.
  void saveScreenshot() {
    device_.waitIdle();
    host::FrameRenderer offscreen(device_, host::OffscreenTarget::kColorFormat,
                                  renderer_.style());
    offscreen.setLineMode(renderer_.lineMode());
    offscreen.setSettings(renderer_.settings());
    const host::OffscreenTarget target(device_, presenter_->extent());
    char name[64];
    do  // the next number no file has yet: an earlier run's screenshots stay
      std::snprintf(name, sizeof(name), "lava-screenshot-%03u.png", screenshots_++);
    while (access(name, F_OK) == 0 && screenshots_ < 100000);
    host::writePng(name, target.extent().width, target.extent().height,
                   host::renderOffscreen(device_, offscreen, *simulation_, target, camera_));
    std::printf("demo: saved %s\n", name);
  }

  // The input applied, the panel built and its requests taken.
  void buildUi() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    input_.apply(controls_, camera_);
    buildPanel();
    ImGui::Render();
    applyRequests();
  }

  // The frame's steps: taken on the CPU, or planned into slot `index` for the device.
  void simulate(uint32_t index, double frameSeconds) {
    const uint32_t steps = stepsFor(frameSeconds);
    if (cpu_) {
      stepOnCpu(steps);
    } else {
      // This slot's previous frame has finished: its schedule may be planned over.
      simulation_->update(index, steps);
    }
    simulatedSeconds_ += double(steps) * double(scene_.h());
  }

  // One frame: simulate, draw, present; `lastOfRun`: the last of a run of --frames N. False when
  // nothing could be drawn (minimised).
  bool drawFrame(double frameSeconds, bool lastOfRun) {
    if (glfwGetWindowAttrib(window_.handle, GLFW_ICONIFIED)) return false;
    resized_ |= input_.takeResized();
    if (resized_) {
      if (!presenter_->resize(framebufferSize())) return false;
      ui_->forgetTargets();
      ImGui_ImplVulkan_SetMinImageCount(2);
      resized_ = false;
    }
    const uint32_t index = frame_ % kFramesInFlight;
    FrameSlot& slot = slots_[index];
    VkFence fence = slot.inFlight;
    VkDevice device = device_.handles().device;
    if (const VkResult waited = vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX);
        waited != VK_SUCCESS) {
      vkDeviceWaitIdle(device);  // the frames in flight may still run
      throw VulkanError(waited, "vkWaitForFences", __FILE__, __LINE__);
    }
    readTimings(index);

    const host::FrameTarget target = presenter_->acquire(index);
    if (!target.color) {
      resized_ = true;
      return false;
    }

    buildUi();
    simulate(index, frameSeconds);

    VK_CHECK(vkResetFences(device, 1, &fence));
    VkCommandBuffer commands = slot.commands;
    VK_CHECK(vkResetCommandBuffer(commands, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(commands, &begin));
    // Timed about ten times a second (a timed frame costs a CPU device a pass over every
    // tile), and the last frame of a run of --frames N, so that its summary has GPU times
    // however fast it ran.
    const double now = glfwGetTime();
    const bool timed = now - lastTimed_ >= 0.1 || now < lastTimed_ || lastOfRun;
    if (timed) {
      lastTimed_ = now;
      timer_.recordStart(commands, index);
    }
    if (!cpu_) simulation_->recordSimulate(commands, index);
    if (timed) timer_.recordSimulated(commands, index);
    const auto overlay = [&](VkCommandBuffer c) {
      if (controls_.showPanel) ui_->record(c, target);
    };
    renderer_.record(commands, index, *simulation_, target, camera_, overlay);
    presenter_->recordAfterFrame(commands, index);
    if (timed) timer_.recordEnd(commands, index);
    VK_CHECK(vkEndCommandBuffer(commands));

    if (!presenter_->submitAndPresent(commands, fence, index)) resized_ = true;
    ++frame_;
    return true;
  }

  DemoOptions options_;
  Scene scene_;
  GlfwWindow window_;
  DemoInput input_{window_.handle};  // before Dear ImGui (ui_), which chains to its callbacks
  Device device_;
  PresentPath path_;
  Surface surface_;
  VkSurfaceFormatKHR format_;
  std::unique_ptr<CpuSimulation> cpu_;  // steps the run, with --backend cpu or cpu-simd
  double cpuMs_ = 0.0;                  // cpu_'s time a frame, smoothed
  std::unique_ptr<GpuSimulation> simulation_;  // steps and draws the run, or draws cpu_'s
  host::FrameRenderer renderer_;
  FrameTimer timer_;
  std::unique_ptr<Presenter> presenter_;
  std::unique_ptr<Ui> ui_;
  host::OwnedCommandPool pool_;
  std::array<FrameSlot, kFramesInFlight> slots_;
  OrbitCamera camera_;
  uint64_t frame_ = 0;
  bool resized_ = false;
  DemoControls controls_;
  common::StepAccumulator owed_;
  double simulatedSeconds_ = 0.0;  // the steps' sizes summed (h may change in the panel)
  double fps_ = 0.0, simulateMs_ = 0.0, drawMs_ = 0.0;
  // glfwGetTime() of the last timed frame; the first frames are not timed (they draw the
  // cached backdrop and may compile shaders).
  double lastTimed_ = 0.0;
  uint64_t timedFrames_ = 0;
  DemoPanel panel_{options_.scene};
  uint32_t screenshots_ = 0;
};

}  // namespace

DemoSummary runDemoWindow(const DemoOptions& options) {
  GlfwSession glfw;
  Demo demo(options);
  return demo.run();
}

}  // namespace lava::window
