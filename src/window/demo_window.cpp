#include "demo_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <vector>

#include "camera.h"
#include "context.h"
#include "gpu_simulator.h"
#include "image_io.h"
#include "line_renderer.h"
#include "offscreen_target.h"
#include "shm_presenter.h"
#include "swapchain.h"
#include "ui.h"
#include "vk_check.h"

namespace lava {
namespace {

constexpr uint32_t kFramesInFlight = 2;
constexpr uint32_t kStepsPerFrameMax = GpuSimulator::kStepsPerSubmit / kFramesInFlight;
constexpr uint32_t kQueriesPerFrame = 3;  // start, after the simulation, after the draw

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

struct Surface {
  VkInstance instance;
  VkSurfaceKHR handle = VK_NULL_HANDLE;
  Surface(VkInstance i, GLFWwindow* window) : instance(i) {
    VK_CHECK(glfwCreateWindowSurface(instance, window, nullptr, &handle));
  }
  ~Surface() { vkDestroySurfaceKHR(instance, handle, nullptr); }
};

ContextOptions windowContextOptions(const DemoOptions& options) {
  uint32_t count = 0;
  const char** extensions = glfwGetRequiredInstanceExtensions(&count);
  if (!extensions) throw NoDisplay("no Vulkan surface extensions for this display");
  ContextOptions context;
  context.instanceExtensions.assign(extensions, extensions + count);
  context.swapchain = true;
  context.hostImport = true;  // MIT-SHM presentation renders into the X server's memory
  context.validation = options.validation;
  context.syncValidation = options.validation;
  context.deviceIndex = options.device;
  return context;
}

struct FrameSlot {
  VkCommandBuffer commands = VK_NULL_HANDLE;
  UniqueFence inFlight;
  bool timed = false;  // its queries hold results from a finished frame
};

// --present, or when it is not given: MIT-SHM for a CPU device (lavapipe) on an X server
// that can attach our memory, unless vsync was asked for; the swapchain otherwise.
PresentPath choosePresentPath(const DemoOptions& options, const Context& context,
                              GLFWwindow* window) {
  std::string why;
  if (options.present == PresentPath::Shm && !ShmPresenter::available(window, &why))
    throw UsageError("--present: shm is not possible here (" + why + ")");
  if (options.present) return *options.present;
  if (options.vsync || context.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU)
    return PresentPath::Swapchain;
  return ShmPresenter::available(window, nullptr) ? PresentPath::Shm : PresentPath::Swapchain;
}

// The render pass's color format for `path`. A window the driver cannot present to at all
// (a 16-bit X display: Mesa presents to depth 24 and 32 only) is no display for the demo.
VkSurfaceFormatKHR windowFormat(PresentPath path, const Context& context, VkSurfaceKHR surface) {
  if (path == PresentPath::Shm) return {ShmPresenter::kFormat, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
  const std::optional<VkSurfaceFormatKHR> format = Swapchain::chooseFormat(context, surface);
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
        context_(windowContextOptions(options)),
        surface_(context_.instance(), window_.handle),
        path_(choosePresentPath(options, context_, window_.handle)),
        format_(windowFormat(path_, context_, surface_.handle)),
        simulator_(std::make_unique<GpuSimulator>(context_, scene_)),
        renderer_(context_, *simulator_, format_.format,
                  path_ == PresentPath::Shm ? ShmPresenter::kFinalLayout
                                            : VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) {
    if (path_ == PresentPath::Shm)
      presenter_ = std::make_unique<ShmPresenter>(context_, window_.handle, renderer_.renderPass(),
                                                  kFramesInFlight);
    else
      presenter_ = std::make_unique<Swapchain>(context_, surface_.handle, renderer_.renderPass(),
                                               format_, options.vsync, kFramesInFlight);
    if (!presenter_->resize(framebufferSize())) throw NoDisplay("the window has no area");
    renderer_.setMode(options.lines);
    simulator_->advance(stepsIn(scene_, options.warmup));
    glfwSetWindowUserPointer(window_.handle, this);
    // Key presses are queued as they arrive (Dear ImGui, set up next, chains to this):
    // ImGui 1.86 keeps only whether a key is down when a frame starts, so a tap pressed and
    // released within one slow frame would be lost.
    glfwSetKeyCallback(window_.handle, [](GLFWwindow* w, int key, int, int action, int) {
      if (action == GLFW_PRESS)
        static_cast<Demo*>(glfwGetWindowUserPointer(w))->pressed_.push_back(key);
    });
    ui_ = std::make_unique<Ui>(context_, window_.handle, renderer_.renderPass(),
                               presenter_->imageCount());
    createFrameSlots();
    glfwSetFramebufferSizeCallback(window_.handle, [](GLFWwindow* w, int, int) {
      static_cast<Demo*>(glfwGetWindowUserPointer(w))->resized_ = true;
    });
  }

  ~Demo() { vkDeviceWaitIdle(context_.device()); }

  DemoSummary run() {
    const auto start = std::chrono::steady_clock::now();
    auto last = start;
    uint32_t presented = 0;
    for (uint64_t iteration = 0; !glfwWindowShouldClose(window_.handle); ++iteration) {
      glfwPollEvents();
      if (options_.exercise) exercise(iteration);
      const auto now = std::chrono::steady_clock::now();
      const double frameSeconds = std::chrono::duration<double>(now - last).count();
      last = now;
      if (!drawFrame(frameSeconds)) {
        glfwWaitEventsTimeout(0.02);  // minimised: wait without spinning
        continue;
      }
      fps_ = fps_ * 0.9 + 0.1 / std::max(frameSeconds, 1e-6);
      ++presented;
      if (options_.frames && presented >= options_.frames) break;
    }
    presenter_->flush();
    VK_CHECK(vkDeviceWaitIdle(context_.device()));
    DemoSummary summary;
    summary.frames = presented;
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.size = presenter_->extent();
    summary.device = context_.properties().deviceName;
    summary.presentMode = presenter_->name();
    summary.simulateMs = simulateMs_;
    summary.drawMs = drawMs_;
    for (const std::string& m : context_.takeValidationMessages()) {
      std::fprintf(stderr, "lava: validation: %s\n", m.c_str());
      ++summary.validationMessages;
    }
    return summary;
  }

 private:
  VkExtent2D framebufferSize() const {
    if (minimisedByExercise_) return {0, 0};
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
  }

  void createFrameSlots() {
    VkDevice device = context_.device();
    VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queryInfo.queryCount = kQueriesPerFrame * kFramesInFlight;
    VkQueryPool queries = VK_NULL_HANDLE;
    VK_CHECK(vkCreateQueryPool(device, &queryInfo, nullptr, &queries));
    queries_ = UniqueQueryPool(device, queries);
    for (FrameSlot& slot : slots_) {
      VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
      alloc.commandPool = context_.commandPool();
      alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      alloc.commandBufferCount = 1;
      VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &slot.commands));
      VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      VkFence fence = VK_NULL_HANDLE;
      VK_CHECK(vkCreateFence(device, &fenceInfo, nullptr, &fence));
      slot.inFlight = UniqueFence(device, fence);
    }
  }

  // Resizes, minimises and restores on a schedule of loop iterations (for tests).
  void exercise(uint64_t iteration) {
    const int w = int(options_.size.width), h = int(options_.size.height);
    switch (iteration) {
      case 60:
        glfwSetWindowSize(window_.handle, w * 3 / 4, h * 3 / 4);
        break;
      case 120:
        glfwSetWindowSize(window_.handle, w / 2, h / 3);
        break;
      case 180:
        // Without a window manager (bare Xvfb) iconifying changes nothing, so the exercise
        // also reports the 0x0 framebuffer a minimised window has on other systems.
        glfwIconifyWindow(window_.handle);
        minimisedByExercise_ = true;
        resized_ = true;
        break;
      case 200:
        glfwRestoreWindow(window_.handle);
        minimisedByExercise_ = false;
        resized_ = true;
        break;
      case 240:
        glfwSetWindowSize(window_.handle, w, h);
        break;
      default:
        break;
    }
  }

  void readTimings(FrameSlot& slot, uint32_t index) {
    if (!slot.timed) return;
    uint64_t stamps[kQueriesPerFrame];
    if (vkGetQueryPoolResults(context_.device(), queries_, index * kQueriesPerFrame,
                              kQueriesPerFrame, sizeof(stamps), stamps, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
      return;
    const double period = context_.limits().timestampPeriod * 1e-6;  // ticks to ms
    simulateMs_ = simulateMs_ * 0.9 + 0.1 * double(stamps[1] - stamps[0]) * period;
    drawMs_ = drawMs_ * 0.9 + 0.1 * double(stamps[2] - stamps[1]) * period;
  }

  // Steps owed for this frame: a fixed h decoupled from the frame rate (at most 0.1 s of
  // simulated time per frame, so a stall does not snowball).
  uint32_t stepsFor(double frameSeconds) {
    if (stepOnce_) {
      stepOnce_ = false;
      return 1;
    }
    if (paused_) return 0;
    owedSeconds_ += std::min(frameSeconds, 0.1) * speed_;
    const double steps = std::floor(owedSeconds_ / double(scene_.dt));
    owedSeconds_ -= steps * double(scene_.dt);
    return static_cast<uint32_t>(std::min(steps, double(kStepsPerFrameMax)));
  }

  void handleInput() {
    ImGuiIO& io = ImGui::GetIO();
    for (const int key : pressed_) {
      if (io.WantCaptureKeyboard) break;  // typed into the panel
      switch (key) {
        case GLFW_KEY_SPACE:
          paused_ = !paused_;
          break;
        case GLFW_KEY_N:
          stepOnce_ = true;
          break;
        case GLFW_KEY_R:
          reset_ = true;
          break;
        case GLFW_KEY_P:
          screenshot_ = true;
          break;
        case GLFW_KEY_H:
          showUi_ = !showUi_;
          break;
        case GLFW_KEY_ESCAPE:
          glfwSetWindowShouldClose(window_.handle, 1);
          break;
        default:
          break;
      }
    }
    pressed_.clear();
    if (!io.WantCaptureMouse) {
      if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
        camera_.yaw -= io.MouseDelta.x * 0.006f;
        camera_.pitch = std::clamp(camera_.pitch + io.MouseDelta.y * 0.006f, -0.05f, 1.5f);
      }
      if (ImGui::IsMouseDragging(ImGuiMouseButton_Right))
        camera_.target.y += io.MouseDelta.y * 0.01f;
      camera_.distance = std::clamp(camera_.distance * std::pow(0.9f, io.MouseWheel), 0.5f, 60.0f);
    }
  }

  void buildUi() {
    if (!showUi_) return;
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("Lava", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%s", context_.properties().deviceName);
    ImGui::Text("%.1f fps   GPU: simulate %.2f ms, draw %.2f ms", fps_, simulateMs_, drawMs_);
    const uint64_t alive = std::min<uint64_t>(simulator_->clock().serial, scene_.particles);
    ImGui::Text("alive %llu / %u   t = %.2f s", static_cast<unsigned long long>(alive),
                scene_.particles, double(simulator_->clock().steps) * double(scene_.dt));
    ImGui::Checkbox("pause [Space]", &paused_);
    ImGui::SameLine();
    if (ImGui::Button("step [N]")) stepOnce_ = true;
    ImGui::SameLine();
    if (ImGui::Button("reset [R]")) reset_ = true;
    ImGui::SameLine();
    if (ImGui::Button("screenshot [P]")) screenshot_ = true;
    ImGui::SliderFloat("speed", &speed_, 0.0f, 4.0f);
    bool splat = renderer_.mode() == LineMode::Splat;
    if (ImGui::Checkbox("compute line splatting (off: graphics pipeline)", &splat))
      renderer_.setMode(splat ? LineMode::Splat : LineMode::Pipeline);

    // Closed at start: the panel is drawn every frame, and on a CPU device a short panel
    // costs a fraction of a long one (docs/benchmarks.md).
    if (ImGui::CollapsingHeader("scene parameters")) {
      Scene s = scene_;
      float rate = float(s.rate);
      ImGui::SliderFloat("rate (1/s)", &rate, 0.0f, 100000.0f, "%.0f",
                         ImGuiSliderFlags_Logarithmic);
      s.rate = rate;
      ImGui::SliderFloat("dt (s)", &s.dt, 0.0001f, 0.01f, "%.4f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat("gravity (m/s2)", &s.gravity, -20.0f, 30.0f);
      ImGui::SliderFloat("restitution", &s.restitution, 0.0f, 1.0f);
      ImGui::SliderFloat("friction (kept)", &s.friction, 0.0f, 1.0f);
      ImGui::SliderFloat("line scale (s)", &s.lineScale, 0.0f, 0.2f);
      ImGui::SliderFloat3("emitter (m)", &s.emitter.x, -3.0f, 3.0f);
      ImGui::SliderFloat("emitter radius (m)", &s.emitterRadius, 0.0f, 2.0f);
      ImGui::SliderFloat3("velocity (m/s)", &s.velocity.x, -15.0f, 15.0f);
      ImGui::SliderFloat3("spread (m/s)", &s.spread.x, 0.0f, 8.0f);
      ImGui::SliderFloat("mass (kg)", &s.mass, 0.05f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat3("wind (N)", &s.wind.x, -10.0f, 10.0f);
      ImGui::SliderFloat("drag (N s/m)", &s.drag, 0.0f, 5.0f);
      int seed = int(s.seed & 0x7fffffff);
      ImGui::InputInt("seed", &seed);
      s.seed = uint32_t(std::max(seed, 0));
      s.dt = std::max(s.dt, 1e-5f);
      s.mass = std::max(s.mass, 1e-3f);
      scene_ = s;
      simulator_->setScene(scene_);

      ImGui::InputInt("particles", &pendingParticles_, 1024, 65536);
      pendingParticles_ = std::clamp(pendingParticles_, 1,
                                     int(std::min<uint64_t>(maxParticles(context_), 1u << 30)));
      ImGui::SameLine();
      if (ImGui::Button("restart")) restart_ = true;
    }
    ImGui::TextDisabled("drag: orbit  right-drag: height  wheel: zoom  H: hide");
    ImGui::End();
  }

  void applyRequests() {
    if (restart_ || reset_) {
      VK_CHECK(vkDeviceWaitIdle(context_.device()));
      if (restart_) {
        scene_.particles = uint32_t(pendingParticles_);
        simulator_.reset();
        simulator_ = std::make_unique<GpuSimulator>(context_, scene_);
        renderer_.bind(*simulator_);
      } else {
        simulator_->load(initialState(scene_));
      }
      restart_ = reset_ = false;
      owedSeconds_ = 0.0;
    }
    if (screenshot_) {
      screenshot_ = false;
      VK_CHECK(vkDeviceWaitIdle(context_.device()));
      LineRenderer offscreen(context_, *simulator_, OffscreenTarget::kColorFormat,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      offscreen.setMode(renderer_.mode());
      OffscreenTarget target(context_, offscreen.renderPass(), presenter_->extent());
      char name[64];
      std::snprintf(name, sizeof(name), "lava-screenshot-%03u.png", screenshots_++);
      writePng(name, target.extent().width, target.extent().height,
               renderOffscreen(context_, offscreen, target, camera_, scene_));
      std::printf("demo: saved %s\n", name);
    }
  }

  // One frame: simulate, draw, present. False when nothing could be drawn (minimised).
  bool drawFrame(double frameSeconds) {
    if (minimisedByExercise_ || glfwGetWindowAttrib(window_.handle, GLFW_ICONIFIED)) return false;
    if (resized_) {
      if (!presenter_->resize(framebufferSize())) return false;
      ImGui_ImplVulkan_SetMinImageCount(2);
      resized_ = false;
    }
    const uint32_t index = frame_ % kFramesInFlight;
    FrameSlot& slot = slots_[index];
    VkFence fence = slot.inFlight;
    VK_CHECK(vkWaitForFences(context_.device(), 1, &fence, VK_TRUE, UINT64_MAX));
    readTimings(slot, index);

    const RenderTarget target = presenter_->acquire(index);
    if (!target.framebuffer) {
      resized_ = true;
      return false;
    }

    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    handleInput();
    buildUi();
    ImGui::Render();
    applyRequests();
    const uint32_t steps = stepsFor(frameSeconds);

    VK_CHECK(vkResetFences(context_.device(), 1, &fence));
    VkCommandBuffer commands = slot.commands;
    VK_CHECK(vkResetCommandBuffer(commands, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(commands, &begin));
    const uint32_t query = index * kQueriesPerFrame;
    vkCmdResetQueryPool(commands, queries_, query, kQueriesPerFrame);
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, query);
    if (steps > 0) {
      const uint32_t first = index * kStepsPerFrameMax;  // this slot's schedule entries
      simulator_->planSteps(first, steps);
      simulator_->recordSteps(commands, first, steps);
    }
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries_, query + 1);
    renderer_.record(commands, target, camera_, scene_, [](VkCommandBuffer c) {
      ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), c);
    });
    presenter_->recordAfterPass(commands, index);
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, query + 2);
    VK_CHECK(vkEndCommandBuffer(commands));

    if (!presenter_->submitAndPresent(commands, fence, index)) resized_ = true;
    slot.timed = true;
    ++frame_;
    return true;
  }

  DemoOptions options_;
  Scene scene_;
  GlfwWindow window_;
  Context context_;
  Surface surface_;
  PresentPath path_;
  VkSurfaceFormatKHR format_;
  std::unique_ptr<GpuSimulator> simulator_;
  LineRenderer renderer_;
  std::unique_ptr<Presenter> presenter_;
  std::unique_ptr<Ui> ui_;
  UniqueQueryPool queries_;
  std::array<FrameSlot, kFramesInFlight> slots_;
  OrbitCamera camera_;
  uint64_t frame_ = 0;
  bool resized_ = false;
  bool minimisedByExercise_ = false;
  bool paused_ = false, stepOnce_ = false, reset_ = false, restart_ = false, screenshot_ = false;
  std::vector<int> pressed_;  // GLFW keys pressed since the last frame, in order
  bool showUi_ = true;
  float speed_ = 1.0f;
  double owedSeconds_ = 0.0;
  double fps_ = 0.0, simulateMs_ = 0.0, drawMs_ = 0.0;
  int pendingParticles_ = int(options_.scene.particles);
  uint32_t screenshots_ = 0;
};

}  // namespace

DemoSummary runDemoWindow(const DemoOptions& options) {
  GlfwSession glfw;
  Demo demo(options);
  return demo.run();
}

}  // namespace lava
