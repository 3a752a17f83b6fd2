// Lava as a host embeds it (docs/library.md): the host's own instance and device, borrowed and
// never destroyed; the simulation recorded into the host's command buffers with frames in flight
// and a step count that changes every frame, bit-identical to the CPU reference; lines drawn into a
// host image of a format Lava was not written for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "common/passes.h"
#include "host/frame_renderer.h"
#include "lava/camera.h"
#include "host/offscreen.h"
#include "lava/lava.h"
#include "lava/validation.h"
#include "test_scenes.h"
#include "vulkan_host.h"
#include "vulkan_test.h"

namespace lava {
namespace {

// A host's instance and device, made without Lava, with the validation layer (required) and
// a messenger of the host's own: the examples' host (examples/common/vulkan_host.h).
// `apiVersion`: the host's Vulkan version (VkApplicationInfo): on 1.2 dynamic rendering is
// the extension, enabled because deviceRequirements() says so.
class HostDevice : public vkhost::Device {
 public:
  explicit HostDevice(uint32_t apiVersion = VK_API_VERSION_1_3)
      : vkhost::Device(options(apiVersion)) {}

 private:
  static vkhost::DeviceOptions options(uint32_t apiVersion) {
    vkhost::DeviceOptions o;
    o.name = "embedding test";
    o.apiVersion = apiVersion;
    o.requireValidation = true;
    o.countGeneral = true;  // any message of the layer fails the test
    return o;
  }
};

class Embedding : public ::testing::TestWithParam<uint32_t> {};

TEST_P(Embedding, FramesInFlightWithChangingStepCountsMatchTheCpu) {
  HostDevice host;
  {
    Device device(host.handles);
    EXPECT_FALSE(device.ownsHandles());
    Scene scene;
    scene.emitters[0].particles = 3000;
    scene.emitters[0].rate = 25000.0;  // wraps the ring several times per second
    device.setFramesInFlight(3);
    GpuSimulationOptions options;
    options.maxStepsPerFrame = 64;
    options.stepsPerDispatch = GetParam();
    GpuSimulation gpu(device, scene, options);
    CpuSimulation cpu(scene);
    vkhost::Frames frames(host.handles, device.framesInFlight());
    uint64_t steps = 0;
    for (uint32_t frame = 0; frame < 60; ++frame) {
      const uint32_t slot = frame % device.framesInFlight();
      const uint32_t count = (frame * 7) % 23;  // 0 some frames, up to 22
      VkCommandBuffer commands = frames.begin(slot);
      gpu.update(slot, count);
      if (count > 0) {  // planning over steps not recorded yet would lose them
        EXPECT_THROW(gpu.update(slot, count), InvalidArgument);
        EXPECT_EQ(gpu.step(), steps + count);
      }
      gpu.recordSimulate(commands, slot);
      gpu.recordSimulate(commands, slot);  // a second record of the same plan records nothing
      frames.submit(slot);
      steps += count;
    }
    vkDeviceWaitIdle(host.handles.device);
    EXPECT_EQ(gpu.step(), steps);
    cpu.advance(steps);
    const State g = gpu.state(), c = cpu.state();
    EXPECT_EQ(g.step, c.step);
    EXPECT_EQ(g.clocks[0].serial, c.clocks[0].serial);
    const Comparison diff = compare(g.particles, c.particles);
    EXPECT_EQ(diff.equal, diff.particles) << "max ULP " << diff.maxUlp;
  }
  // Lava destroyed nothing of the host's: its device still works, and is destroyed by the
  // host without complaint.
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 256;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  EXPECT_EQ(vkCreateBuffer(host.handles.device, &info, nullptr, &buffer), VK_SUCCESS);
  vkDestroyBuffer(host.handles.device, buffer, nullptr);
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// Fused steps per dispatch: one (memory-bound), a prime, the default.
INSTANTIATE_TEST_SUITE_P(StepsPerDispatch, Embedding, ::testing::Values(1u, 7u, 256u));

// Lava's own calls, counted: Lava loads every Vulkan function through the host's
// getInstanceProcAddr, which here hands out counting wrappers of the calls that submit or
// wait. The host's own calls go to the loader and are not counted.
struct LavaCalls {
  int submits = 0, queueWaits = 0, deviceWaits = 0, fenceWaits = 0;
  std::vector<std::string> otherSubmitsOrWaits;  // any other such function Lava loaded
  PFN_vkGetDeviceProcAddr getDeviceProcAddr = nullptr;
  PFN_vkQueueSubmit queueSubmit = nullptr;
  PFN_vkQueueWaitIdle queueWaitIdle = nullptr;
  PFN_vkDeviceWaitIdle deviceWaitIdle = nullptr;
  PFN_vkWaitForFences waitForFences = nullptr;
  int total() const { return submits + queueWaits + deviceWaits + fenceWaits; }
};
LavaCalls lavaCalls;

VKAPI_ATTR VkResult VKAPI_CALL countedQueueSubmit(VkQueue q, uint32_t n, const VkSubmitInfo* s,
                                                  VkFence f) {
  ++lavaCalls.submits;
  return lavaCalls.queueSubmit(q, n, s, f);
}
VKAPI_ATTR VkResult VKAPI_CALL countedQueueWaitIdle(VkQueue q) {
  ++lavaCalls.queueWaits;
  return lavaCalls.queueWaitIdle(q);
}
VKAPI_ATTR VkResult VKAPI_CALL countedDeviceWaitIdle(VkDevice d) {
  ++lavaCalls.deviceWaits;
  return lavaCalls.deviceWaitIdle(d);
}
VKAPI_ATTR VkResult VKAPI_CALL countedWaitForFences(VkDevice d, uint32_t n, const VkFence* f,
                                                    VkBool32 all, uint64_t timeout) {
  ++lavaCalls.fenceWaits;
  return lavaCalls.waitForFences(d, n, f, all, timeout);
}

PFN_vkVoidFunction counted(const char* name, PFN_vkVoidFunction real) {
  const std::string n = name;
  if (!real) return real;
  if (n == "vkQueueSubmit") {
    lavaCalls.queueSubmit = reinterpret_cast<PFN_vkQueueSubmit>(real);
    return reinterpret_cast<PFN_vkVoidFunction>(countedQueueSubmit);
  }
  if (n == "vkQueueWaitIdle") {
    lavaCalls.queueWaitIdle = reinterpret_cast<PFN_vkQueueWaitIdle>(real);
    return reinterpret_cast<PFN_vkVoidFunction>(countedQueueWaitIdle);
  }
  if (n == "vkDeviceWaitIdle") {
    lavaCalls.deviceWaitIdle = reinterpret_cast<PFN_vkDeviceWaitIdle>(real);
    return reinterpret_cast<PFN_vkVoidFunction>(countedDeviceWaitIdle);
  }
  if (n == "vkWaitForFences") {
    lavaCalls.waitForFences = reinterpret_cast<PFN_vkWaitForFences>(real);
    return reinterpret_cast<PFN_vkVoidFunction>(countedWaitForFences);
  }
  if (n.find("Submit") != std::string::npos || n.find("Wait") != std::string::npos)
    lavaCalls.otherSubmitsOrWaits.push_back(n);
  return real;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countedGetDeviceProcAddr(VkDevice device,
                                                                  const char* name) {
  return counted(name, lavaCalls.getDeviceProcAddr(device, name));
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countedGetInstanceProcAddr(VkInstance instance,
                                                                    const char* name) {
  if (std::string(name) == "vkGetDeviceProcAddr") {
    lavaCalls.getDeviceProcAddr =
        reinterpret_cast<PFN_vkGetDeviceProcAddr>(vkGetInstanceProcAddr(instance, name));
    return reinterpret_cast<PFN_vkVoidFunction>(countedGetDeviceProcAddr);
  }
  return counted(name, vkGetInstanceProcAddr(instance, name));
}

// A host that only records: from Lava's device to its destruction, frames of simulation and
// drawing (both renderers, the lava look with its glow, a resize that also rebuilds the
// host's frames with one more in flight, and a live setScene()) through the host's own
// command buffers, and Lava never submits or waits. What it recorded is right: the host's
// own read-back of the particles equals the CPU reference bit for bit (the particles'
// initial state, too, was recorded, not uploaded).
class EmbeddingRecordOnly : public ::testing::TestWithParam<uint32_t> {};

TEST_P(EmbeddingRecordOnly, LavaMakesNoSubmitOrWaitFromCreationToDestruction) {
  HostDevice host(GetParam());
  // Vulkan 1.3's vkCmdBeginRendering, or the extension's on a 1.2 host.
  const bool core = GetParam() >= VK_API_VERSION_1_3;
  const auto beginRendering = reinterpret_cast<PFN_vkCmdBeginRendering>(vkGetDeviceProcAddr(
      host.handles.device, core ? "vkCmdBeginRendering" : "vkCmdBeginRenderingKHR"));
  const auto endRendering = reinterpret_cast<PFN_vkCmdEndRendering>(vkGetDeviceProcAddr(
      host.handles.device, core ? "vkCmdEndRendering" : "vkCmdEndRenderingKHR"));
  ASSERT_NE(beginRendering, nullptr);
  ASSERT_NE(endRendering, nullptr);
  lavaCalls = LavaCalls{};
  DeviceHandles handles = host.handles;
  handles.getInstanceProcAddr = countedGetInstanceProcAddr;
  const VkDevice vkDevice = handles.device;
  const VkExtent2D extents[2] = {{160, 120}, {200, 100}};
  Scene scene;
  scene.emitters[0].particles = 4096;
  scene.emitters[0].rate = 20000.0;
  constexpr uint32_t kFrames = 24, kSteps = 17;
  Scene edited = scene;  // from frame kFrames / 2 on
  edited.wind = {0.4f, 0.0f, -0.2f};
  edited.emitters[0].rate = 9000.0;
  std::vector<Particle> readBack;
  {
    Device device(handles);
    GpuSimulation gpu(device, scene);
    LineRenderer lines(device, {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_UNDEFINED});
    auto frames = std::make_unique<vkhost::Frames>(host.handles, device.framesInFlight());

    // The host's target (one per size) and a buffer it reads the particles back into.
    const vkhost::Image targets[2] = {
        {host.handles, extents[0], VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
         VK_IMAGE_ASPECT_COLOR_BIT},
        {host.handles, extents[1], VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
         VK_IMAGE_ASPECT_COLOR_BIT}};
    const vkhost::Readback readback(host.handles, scene.particles() * sizeof(Particle));

    OrbitCamera camera;
    for (uint32_t frame = 0; frame <= kFrames; ++frame) {
      const int t = frame < kFrames / 2 ? 0 : 1;
      if (frame == kFrames / 2) {  // a resize: the host has waited for the frames before it
        vkDeviceWaitIdle(vkDevice);
        frames.reset();  // and its swapchain came back with more images
        device.setFramesInFlight(3);
        frames = std::make_unique<vkhost::Frames>(host.handles, 3);
        lines.setExtent(extents[t]);
        gpu.setScene(edited);  // a live edit: no submission or wait either
      } else if (frame == 0) {
        lines.setExtent(extents[t]);
      }
      const uint32_t slot = frame % device.framesInFlight();
      lines.setMode(frame % 4 == 0 ? LineMode::Lines : LineMode::Splat);
      VkCommandBuffer commands = frames->begin(slot);
      if (frame == kFrames) {  // the host's read-back of what the frames computed
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr,
                                VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT};
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &barrier, 0, nullptr, 0,
                             nullptr);
        for (const ParticleChunk& chunk : gpu.chunks()) {
          const VkBufferCopy region{0, chunk.first * sizeof(Particle),
                                    chunk.count * sizeof(Particle)};
          vkCmdCopyBuffer(commands, chunk.buffer, readback.buffer, 1, &region);
        }
        frames->submit(slot);
        break;
      }
      gpu.update(slot, kSteps);
      gpu.recordSimulate(commands, slot);
      const View view{camera.viewProj(float(extents[t].width) / float(extents[t].height)),
                      extents[t], camera.eye()};
      lines.recordPrepare(commands, slot, gpu, view);
      VkImageMemoryBarrier toColor{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
      toColor.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
      toColor.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
      toColor.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
      toColor.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      toColor.srcQueueFamilyIndex = toColor.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      toColor.image = targets[t].image;
      toColor.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                           VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr,
                           1, &toColor);
      VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      color.imageView = targets[t].view;
      color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
      rendering.renderArea = {{0, 0}, extents[t]};
      rendering.layerCount = 1;
      rendering.colorAttachmentCount = 1;
      rendering.pColorAttachments = &color;
      beginRendering(commands, &rendering);
      lines.recordDraw(commands, slot, gpu, view);
      endRendering(commands);
      frames->submit(slot);
    }
    vkDeviceWaitIdle(vkDevice);
    const std::vector<uint8_t> bytes = readback.read();
    readBack.resize(scene.particles());
    std::memcpy(readBack.data(), bytes.data(), bytes.size());
  }  // Lava's objects and device destroyed
  EXPECT_EQ(lavaCalls.submits, 0);
  EXPECT_EQ(lavaCalls.queueWaits, 0);
  EXPECT_EQ(lavaCalls.deviceWaits, 0);
  EXPECT_EQ(lavaCalls.fenceWaits, 0);
  for (const std::string& name : lavaCalls.otherSubmitsOrWaits)
    ADD_FAILURE() << "Lava loaded " << name << ", which this test does not count";
  ASSERT_NE(lavaCalls.queueSubmit, nullptr) << "the counting wrappers were not used";

  CpuSimulation cpu(scene);
  cpu.advance(uint64_t{kFrames / 2} * kSteps);
  cpu.setScene(edited);
  cpu.advance(uint64_t{kFrames - kFrames / 2} * kSteps);
  const Comparison diff = compare(readBack, cpu.state().particles);
  EXPECT_EQ(diff.equal, diff.particles) << "max ULP " << diff.maxUlp;

  // The counter counts: a blocking helper submits and waits through it.
  {
    Device device(handles);
    GpuSimulation gpu(device, scene);
    gpu.advance(3);
  }
  EXPECT_GT(lavaCalls.submits, 0);
  EXPECT_GT(lavaCalls.fenceWaits, 0);

  // Each submission of advance() carries at most maxParticleStepsPerSubmission particle-
  // steps: 10 steps of the scene's slots each, so 95 steps take 10 submissions; by default
  // (2^26) one. The same bytes either way.
  {
    Device device(handles);
    GpuSimulationOptions bounded;
    bounded.maxParticleStepsPerSubmission = 10 * scene.particles() + 7;
    GpuSimulation split(device, scene, bounded), whole(device, scene);
    int before = lavaCalls.submits;
    split.advance(95);
    EXPECT_EQ(lavaCalls.submits - before, 10);
    before = lavaCalls.submits;
    whole.advance(95);
    EXPECT_EQ(lavaCalls.submits - before, 1);
    const Comparison same = compare(split.state().particles, whole.state().particles);
    EXPECT_EQ(same.equal, same.particles);
    bounded.maxParticleStepsPerSubmission = 0;
    EXPECT_THROW(GpuSimulation(device, scene, bounded), InvalidArgument);
  }
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// Vulkan 1.3, and a host of Vulkan 1.2 with dynamic rendering as an extension.
INSTANTIATE_TEST_SUITE_P(HostVersions, EmbeddingRecordOnly,
                         ::testing::Values(VK_API_VERSION_1_3, VK_API_VERSION_1_2),
                         [](const ::testing::TestParamInfo<uint32_t>& version) {
                           return version.param >= VK_API_VERSION_1_3 ? "Vulkan13" : "Vulkan12";
                         });

// A host with three frames in flight that told Lava two: its third slot is refused at once
// by the simulation and the renderer alike, naming the count and what to pass, on any
// driver (lavapipe, which finishes each frame before the next begins, would never show the
// race a reused slot makes on a GPU). Told three, the same host runs.
TEST(EmbeddingFrameSlots, ASlotPastTheDevicesCountIsRefused) {
  HostDevice host;
  {
    Device device(host.handles);
    ASSERT_EQ(device.framesInFlight(), 2u);  // the default
    Scene scene;
    scene.emitters[0].particles = 1000;
    GpuSimulation gpu(device, scene);
    LineRenderer lines(device, {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_UNDEFINED});
    lines.setExtent({64, 64});
    vkhost::Frames frames(host.handles, 3);  // the host's three fences, in rotation
    OrbitCamera camera;
    const View view{camera.viewProj(1.0f), {64, 64}, camera.eye()};
    const auto runFrames = [&]() {
      uint32_t refused = 0;
      for (uint32_t frame = 0; frame < 6; ++frame) {
        const uint32_t slot = frame % 3;
        VkCommandBuffer commands = frames.begin(slot);
        try {
          gpu.update(slot, 5);
          gpu.recordSimulate(commands, slot);
          lines.recordPrepare(commands, slot, gpu, view);
        } catch (const InvalidArgument& e) {
          ++refused;
          EXPECT_EQ(slot, 2u);
          EXPECT_NE(std::string(e.what()).find(
                        "frame slot 2 is not below the device's 2 frames in flight: pass the "
                        "index of the fence that guards the frame"),
                    std::string::npos)
              << e.what();
          EXPECT_THROW(gpu.recordSimulate(commands, slot), InvalidArgument);
          EXPECT_THROW(lines.recordPrepare(commands, slot, gpu, view), InvalidArgument);
          EXPECT_THROW(lines.recordDraw(commands, slot, gpu, view), InvalidArgument);
        }
        frames.submit(slot);
      }
      return refused;
    };
    EXPECT_EQ(runFrames(), 2u);
    EXPECT_EQ(gpu.step(), 4u * 5u);
    EXPECT_THROW(device.setFramesInFlight(0), InvalidArgument);
    EXPECT_THROW(device.setFramesInFlight(17), InvalidArgument);
    device.setFramesInFlight(3);
    EXPECT_EQ(runFrames(), 0u);
    vkDeviceWaitIdle(host.handles.device);
    CpuSimulation cpu(scene);
    cpu.advance(10u * 5u);
    const Comparison diff = compare(gpu.state().particles, cpu.state().particles);
    EXPECT_EQ(diff.equal, diff.particles) << "max ULP " << diff.maxUlp;
  }
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// The frame recipe with depth (docs/library.md), in the host's render passes and in dynamic
// rendering: the backdrop writes colour and depth in a first pass; the depth goes read-only;
// recordPrepare() splats against it; the lines and the glow draw in a second pass. The same
// frames give the same pixels, byte for byte, in both, with validation and synchronisation
// validation clean. A host that never enabled dynamic rendering for Lava must give passes.
TEST(EmbeddingRenderPass, DrawsWhatDynamicRenderingDraws) {
  HostDevice host;
  const VkDevice vk = host.handles.device;
  constexpr VkFormat kColor = VK_FORMAT_B8G8R8A8_UNORM, kDepth = VK_FORMAT_D32_SFLOAT;
  constexpr VkImageLayout kWrite = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                          kRead = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                          kColorLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  const VkExtent2D extent{192, 128};
  Scene scene;
  scene.emitters[0].particles = 4096;
  scene.emitters[0].rate = 20000.0;
  // A sphere between the camera and the fountain: lines behind it are hidden by the depth.
  Collider sphere;
  sphere.type = ColliderType::Sphere;
  sphere.position = {1.6f, 1.6f, 2.3f};
  sphere.radius = 0.8f;
  scene.colliders.push_back(sphere);
  // And a block of molten rock at the fountain's foot: the flow's surface, drawn in the pass.
  scene.flow.emplace();
  Emitter rock;
  rock.flow = true;
  rock.fill = Fill::Lattice;
  rock.shape = Shape::Box;
  rock.position = {0.5f, 0.06f, 0.8f};
  rock.size = {0.3f, 0.05f, 0.3f};
  rock.mass = scene.flow->density * 0.03f * 0.03f * 0.03f;  // 3 cm apart
  rock.particles = rock.burst = 250;
  rock.rate = 0.0;
  scene.emitters.push_back(rock);
  // The host's attachments (the depth sampled by the splat) and read-back buffer.
  const vkhost::Image images[2] = {
      {host.handles, extent, kColor,
       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
       VK_IMAGE_ASPECT_COLOR_BIT},
      {host.handles, extent, kDepth,
       VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
       VK_IMAGE_ASPECT_DEPTH_BIT}};
  const vkhost::Readback readback(host.handles, VkDeviceSize{extent.width} * extent.height * 4);

  // Pass 0 clears and writes depth (the backdrop's); pass 1 loads both, depth read-only
  // (Lava's lines and glow). Their layouts stay as the subpass uses them: the host's
  // barriers between the passes transition them, as in dynamic rendering.
  VkRenderPass passes[2];
  VkFramebuffer framebuffers[2];
  for (int load = 0; load < 2; ++load) {
    const VkAttachmentLoadOp loadOp =
        load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    const VkImageLayout depthLayout = load ? kRead : kWrite;
    const VkAttachmentDescription a[2] = {
        common::attachment(kColor, loadOp, VK_ATTACHMENT_STORE_OP_STORE, kColorLayout,
                           kColorLayout),
        common::attachment(kDepth, loadOp,
                           load ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE,
                           depthLayout, depthLayout)};
    const VkAttachmentReference color{0, kColorLayout}, depth{1, depthLayout};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color;
    subpass.pDepthStencilAttachment = &depth;
    const VkRenderPassCreateInfo info = common::onePassInfo(a, 2, subpass, nullptr, 0);
    ASSERT_EQ(vkCreateRenderPass(vk, &info, nullptr, &passes[load]), VK_SUCCESS);
    const VkImageView views[2] = {images[0].view, images[1].view};
    const VkFramebufferCreateInfo fb = common::framebufferInfo(passes[load], views, 2, extent);
    ASSERT_EQ(vkCreateFramebuffer(vk, &fb, nullptr, &framebuffers[load]), VK_SUCCESS);
  }

  const auto barrier = vkhost::imageBarrier;
  constexpr VkPipelineStageFlags kTests =
      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  constexpr VkPipelineStageFlags kColorStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  constexpr VkAccessFlags kColorAccess =
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  // 12 frames (lines, then the splat, alternating) in passes or in dynamic rendering; the
  // last frame's pixels.
  const auto run = [&](bool renderPasses) {
    Device device(host.handles);
    GpuSimulation gpu(device, scene);
    RenderFormats backdropTarget{kColor, kDepth}, linesTarget{kColor, kDepth};
    if (renderPasses) {
      backdropTarget.renderPass = passes[0];
      linesTarget.renderPass = passes[1];
    }
    Backdrop backdrop(device, backdropTarget);
    LineRenderer lines(device, linesTarget);
    lines.setExtent(extent);
    vkhost::Frames frames(host.handles, device.framesInFlight());
    OrbitCamera camera;
    const View view{camera.viewProj(float(extent.width) / float(extent.height)), extent,
                    camera.eye()};
    const auto begin = [&](VkCommandBuffer cmd, bool load) {
      if (renderPasses) {
        VkClearValue clear[2]{};
        clear[0].color = {{0.01f, 0.01f, 0.02f, 1.0f}};
        clear[1].depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        info.renderPass = passes[load];
        info.framebuffer = framebuffers[load];
        info.renderArea = {{0, 0}, extent};
        info.clearValueCount = 2;
        info.pClearValues = clear;
        vkCmdBeginRenderPass(cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
        return;
      }
      common::beginFramePass(vkCmdBeginRendering, cmd, images[0].view, images[1].view, extent,
                             load, {{0.01f, 0.01f, 0.02f, 1.0f}}, kWrite);
    };
    const auto end = [&](VkCommandBuffer cmd) {
      if (renderPasses)
        vkCmdEndRenderPass(cmd);
      else
        vkCmdEndRendering(cmd);
    };
    constexpr uint32_t kFrames = 12;
    for (uint32_t frame = 0; frame < kFrames; ++frame) {
      const uint32_t slot = frame % device.framesInFlight();
      lines.setMode(frame % 2 ? LineMode::Splat : LineMode::Lines);
      VkCommandBuffer cmd = frames.begin(slot);
      gpu.update(slot, 13);
      gpu.recordSimulate(cmd, slot);
      // WAR: the last frame's lines, splat and copy read these images.
      barrier(cmd, images[0].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
              kColorLayout, kColorStage | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, kColorStage,
              kColorAccess);
      barrier(cmd, images[1].image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED, kWrite,
              kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, kTests,
              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
      begin(cmd, false);
      backdrop.recordDraw(cmd, view, scene);
      end(cmd);
      // RAW: the second pass loads the colour; the splat samples the depth, the lines test
      // against it.
      barrier(cmd, images[0].image, VK_IMAGE_ASPECT_COLOR_BIT, kColorLayout, kColorLayout,
              kColorStage, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, kColorStage, kColorAccess);
      barrier(cmd, images[1].image, VK_IMAGE_ASPECT_DEPTH_BIT, kWrite, kRead, kTests,
              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
              kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
      lines.recordPrepare(cmd, slot, gpu, view, images[1].view);
      begin(cmd, true);
      lines.recordDraw(cmd, slot, gpu, view);
      end(cmd);
      if (frame + 1 == kFrames) {
        barrier(cmd, images[0].image, VK_IMAGE_ASPECT_COLOR_BIT, kColorLayout,
                VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kColorStage,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, images[0].image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               readback.buffer, 1, &region);
        VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr,
                               VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                             1, &toHost, 0, nullptr, 0, nullptr);
      }
      frames.submit(slot);
    }
    vkDeviceWaitIdle(vk);
    return readback.read();
  };
  const std::vector<uint8_t> dynamic = run(false), passed = run(true);
  size_t lit = 0, differ = 0;
  for (size_t i = 0; i < dynamic.size(); i += 4) {
    lit += dynamic[i + 2] > 150;  // red: lava over the dark backdrop
    differ += std::memcmp(&dynamic[i], &passed[i], 4) != 0;
  }
  EXPECT_GT(lit, 100u);
  EXPECT_EQ(differ, 0u) << "of " << dynamic.size() / 4 << " pixels";

  // Without dynamic rendering enabled, pipelines for formats are refused, passes taken.
  {
    DeviceHandles handles = host.handles;
    handles.dynamicRendering = false;
    Device device(handles);
    EXPECT_THROW(LineRenderer(device, {kColor, kDepth}), InvalidArgument);
    EXPECT_THROW(Backdrop(device, {kColor, kDepth}), InvalidArgument);
    LineRenderer lines(device, {kColor, kDepth, passes[1]});
    Backdrop backdrop(device, {kColor, kDepth, passes[0]});
  }

  for (int i = 0; i < 2; ++i) {
    vkDestroyFramebuffer(vk, framebuffers[i], nullptr);
    vkDestroyRenderPass(vk, passes[i], nullptr);
  }
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// Two simulations on one borrowed device, each built and recorded on a thread of its own
// into the host's command buffers (the host serialises its queue submissions, as Vulkan
// requires): both equal the CPU reference.
TEST(EmbeddingThreads, TwoSimulationsRecordOnTwoThreads) {
  HostDevice host;
  std::mutex queue;
  Device device(host.handles);
  const auto run = [&](uint32_t seed, std::vector<Particle>* out, uint64_t* steps) {
    Scene scene;
    scene.seed = seed;
    scene.emitters[0].particles = 5000;
    scene.emitters[0].rate = 30000.0;
    GpuSimulation gpu(device, scene);
    auto frames = std::make_unique<vkhost::Frames>(host.handles, device.framesInFlight());
    for (uint32_t frame = 0; frame < 40; ++frame) {
      const uint32_t slot = frame % device.framesInFlight();
      const uint32_t count = 5 + (frame * seed) % 13;
      VkCommandBuffer commands = frames->begin(slot);
      gpu.update(slot, count);
      gpu.recordSimulate(commands, slot);
      {
        std::lock_guard<std::mutex> lock(queue);
        frames->submit(slot);
      }
      *steps += count;
    }
    // The host's waits on the device, and Lava's blocking helpers: one thread at a time.
    std::lock_guard<std::mutex> lock(queue);
    frames.reset();
    *out = gpu.state().particles;
  };
  std::vector<Particle> results[2];
  uint64_t steps[2] = {0, 0};
  std::thread a(run, 7u, &results[0], &steps[0]);
  std::thread b(run, 11u, &results[1], &steps[1]);
  a.join();
  b.join();
  const uint32_t seeds[2] = {7u, 11u};
  for (int i = 0; i < 2; ++i) {
    Scene scene;
    scene.seed = seeds[i];
    scene.emitters[0].particles = 5000;
    scene.emitters[0].rate = 30000.0;
    CpuSimulation cpu(scene);
    cpu.advance(steps[i]);
    const Comparison diff = compare(results[i], cpu.state().particles);
    EXPECT_EQ(diff.equal, diff.particles) << "simulation " << i << ": max ULP " << diff.maxUlp;
  }
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// deviceRequirements() asked about a device reports what it offers; a host that tells Lava
// which features it enabled gets an error naming the one missing.
TEST(EmbeddingFeatures, RequirementsAskTheDeviceAndEnabledFeaturesAreChecked) {
  HostDevice host;
  const DeviceRequirements asked =
      deviceRequirements(host.handles.instance, host.handles.physicalDevice);
  EXPECT_TRUE(asked.int64Atomics) << "lavapipe offers shaderInt64 and shaderBufferInt64Atomics";
  ASSERT_EQ(asked.optionalExtensions.size(), 1u);
  EXPECT_STREQ(asked.optionalExtensions[0], VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);

  // The chain the host says it created the device with.
  VkPhysicalDeviceDynamicRenderingFeatures dynamic{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
  dynamic.dynamicRendering = VK_TRUE;
  VkPhysicalDeviceFeatures2 enabled{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enabled.pNext = &dynamic;
  const auto expectError = [&](DeviceHandles handles, const std::string& parameter,
                               const std::string& feature) {
    try {
      Device device(handles);
      ADD_FAILURE() << "accepted without " << feature;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), parameter);
      EXPECT_NE(std::string(e.what()).find(feature), std::string::npos) << e.what();
    }
  };
  DeviceHandles handles = host.handles;
  handles.enabledFeatures = &enabled;
  handles.int64Atomics = true;  // but neither feature in the chain
  expectError(handles, "int64Atomics", "shaderInt64");
  enabled.features.shaderInt64 = VK_TRUE;
  expectError(handles, "int64Atomics", "shaderBufferInt64Atomics");
  handles.int64Atomics = false;
  dynamic.dynamicRendering = VK_FALSE;
  expectError(handles, "enabledFeatures", "dynamicRendering");
  dynamic.dynamicRendering = VK_TRUE;
  {
    Device device(handles);  // what the device really has: accepted
    EXPECT_EQ(device.handles().enabledFeatures, nullptr) << "kept a pointer of the host's";
  }
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// A host's render pass like Dear ImGui's: one colour attachment, cleared, no depth; left in
// TRANSFER_SRC_OPTIMAL for the host's read-back.
VkRenderPass colourOnlyPass(VkDevice vk, VkFormat format) {
  const VkAttachmentDescription a =
      common::attachment(format, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  const VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color;
  VkSubpassDependency dependency{};  // as ImGui's: the attachment's writes after its last use
  dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
  dependency.srcStageMask =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependency.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  dependency.dstAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  VkSubpassDependency after{};  // the copy to the read-back after the pass
  after.srcSubpass = 0;
  after.dstSubpass = VK_SUBPASS_EXTERNAL;
  after.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  after.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  after.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  after.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  const VkSubpassDependency dependencies[2] = {dependency, after};
  const VkRenderPassCreateInfo info = common::onePassInfo(&a, 1, subpass, dependencies, 2);
  VkRenderPass pass = VK_NULL_HANDLE;
  EXPECT_EQ(vkCreateRenderPass(vk, &info, nullptr, &pass), VK_SUCCESS);
  return pass;
}

// One frame in a colour-only host pass of `extent`: the simulation's recorded steps (none
// when `steps` is 0), recordPrepare() without a depth view, the backdrop and the lines in the
// pass; the pixels read back.
std::vector<uint8_t> drawInColourOnlyPass(Device& device, GpuSimulation& gpu, const Scene& scene,
                                          Backdrop& backdrop, LineRenderer& lines,
                                          VkRenderPass pass, VkFormat format, VkExtent2D extent,
                                          const View& view, uint32_t steps) {
  const DeviceHandles& host = device.handles();
  const VkDevice vk = host.device;
  const vkhost::Image image(host, extent, format,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                        VK_IMAGE_ASPECT_COLOR_BIT);
  const vkhost::Readback readback(host, VkDeviceSize{extent.width} * extent.height * 4);
  const VkFramebufferCreateInfo fb = common::framebufferInfo(pass, &image.view, 1, extent);
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  EXPECT_EQ(vkCreateFramebuffer(vk, &fb, nullptr, &framebuffer), VK_SUCCESS);
  vkhost::Frames frames(host, 1);
  VkCommandBuffer cmd = frames.begin(0);
  if (steps > 0) {
    gpu.update(0, steps);
    gpu.recordSimulate(cmd, 0);
  }
  lines.recordPrepare(cmd, 0, gpu, view);
  VkClearValue clear{};
  clear.color = {{0.01f, 0.01f, 0.02f, 1.0f}};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = pass;
  begin.framebuffer = framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = 1;
  begin.pClearValues = &clear;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  backdrop.recordDraw(cmd, view, scene);
  lines.recordDraw(cmd, 0, gpu, view);
  vkCmdEndRenderPass(cmd);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer,
                         1, &region);
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &toHost, 0, nullptr, 0, nullptr);
  frames.submit(0);
  vkDeviceWaitIdle(vk);
  vkDestroyFramebuffer(vk, framebuffer, nullptr);
  return readback.read();
}

using EmbeddingDraw = test::VulkanTest;

TEST_F(EmbeddingDraw, LinesLandInAHostImageOfAnotherChannelOrder) {
  // The same lines into RGBA and BGRA targets: the same pixels, with red and blue swapped,
  // in both looks (the lava look's last pass writes the host's format).
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2500);
  const OrbitCamera camera;
  for (LookStyle style : {LookStyle::Plain, LookStyle::Lava}) {
    SCOPED_TRACE(style == LookStyle::Lava ? "lava look" : "plain look");
    std::vector<uint8_t> images[2];
    const VkFormat formats[2] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM};
    for (int i = 0; i < 2; ++i) {
      host::FrameRenderer renderer(device(), formats[i], style);
      const host::OffscreenTarget target(device(), {200, 150}, formats[i]);
      images[i] = host::renderOffscreen(device(), renderer, simulation, target, camera);
    }
    size_t lit = 0;
    for (size_t p = 0; p < images[0].size(); p += 4) {
      ASSERT_EQ(images[0][p], images[1][p + 2]) << "pixel " << p / 4;
      ASSERT_EQ(images[0][p + 1], images[1][p + 1]);
      ASSERT_EQ(images[0][p + 2], images[1][p]);
      lit += images[0][p] > 120;
    }
    EXPECT_GT(lit, 100u);
  }
}

// A host like Dear ImGui's that destroys and remakes its render pass (colour only, cleared)
// at every resize, and gives Lava the new one only when it makes its renderers: a pass is
// destroyed before the renderers first use it, then remade at each of five sizes, small and
// large enough to switch the splat's and the glow's reads between texel views and storage
// buffers where the device's texel views are small (SwiftShader's 65,536 texels), which
// rebuilds pipelines in setExtent(). Lava keeps no handle of the host's: no validation
// message, and lava is drawn at every size.
TEST_F(EmbeddingDraw, AHostThatRemakesItsRenderPassAtEveryResizeDrawsEveryFrame) {
  const VkDevice vk = device().handles().device;
  constexpr VkFormat kColor = VK_FORMAT_B8G8R8A8_UNORM;
  Scene scene;
  scene.emitters[0].particles = 4096;
  scene.emitters[0].rate = 20000.0;
  GpuSimulation gpu(device(), scene);
  VkRenderPass pass = colourOnlyPass(vk, kColor);
  RenderFormats formats{kColor, VK_FORMAT_UNDEFINED, pass};
  Backdrop backdrop(device(), formats);
  LineRenderer lines(device(), formats);
  OrbitCamera camera;
  const VkExtent2D sizes[] = {{240, 180}, {512, 384}, {160, 120}, {640, 400}, {200, 150}};
  for (const VkExtent2D extent : sizes) {
    SCOPED_TRACE(std::to_string(extent.width) + "x" + std::to_string(extent.height));
    vkDeviceWaitIdle(vk);  // as a host rebuilding its swapchain
    vkDestroyRenderPass(vk, pass, nullptr);
    pass = colourOnlyPass(vk, kColor);
    lines.setExtent(extent);
    const View view{camera.viewProj(float(extent.width) / float(extent.height)), extent,
                    camera.eye()};
    for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
      lines.setMode(mode);
      const std::vector<uint8_t> pixels = drawInColourOnlyPass(
          device(), gpu, scene, backdrop, lines, pass, kColor, extent, view, 40);
      size_t lit = 0;
      for (size_t p = 0; p < pixels.size(); p += 4) lit += pixels[p + 2] > 150;  // red: lava
      EXPECT_GT(lit, 20u) << (mode == LineMode::Splat ? "splat" : "lines");
    }
  }
  vkDestroyRenderPass(vk, pass, nullptr);
}

// A colour-only host pass (no depth of the host's) with setSceneDepth(): Lava draws the
// solids' depth itself, and the splat hides a particle behind the volcano's cone while it
// draws one beside it; without it, the one behind shows through.
TEST_F(EmbeddingDraw, ASceneDepthOfLavasOwnHidesLavaBehindTheConeInAColourOnlyPass) {
  const VkDevice vk = device().handles().device;
  constexpr VkFormat kColor = VK_FORMAT_B8G8R8A8_UNORM;
  constexpr VkExtent2D kExtent{320, 240};
  Scene scene = test::coneScene();
  scene.emitters[0].particles = 1;
  const OrbitCamera camera;
  const View view{camera.viewProj(float(kExtent.width) / float(kExtent.height)), kExtent,
                  camera.eye()};
  const glm::vec3 away = glm::normalize(-glm::vec3(camera.eye().x, 0.0f, camera.eye().z));
  const glm::vec3 across = glm::cross(away, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::vec3 behind = away * 2.2f + glm::vec3(0.0f, 0.3f, 0.0f);
  const glm::vec3 beside = across * 2.6f + glm::vec3(0.0f, 0.3f, 0.0f);
  VkRenderPass pass = colourOnlyPass(vk, kColor);
  const RenderFormats formats{kColor, VK_FORMAT_UNDEFINED, pass};
  Backdrop backdrop(device(), formats);
  LineRenderer lines(device(), formats);
  lines.setExtent(kExtent);
  lines.setMode(LineMode::Splat);
  lines.setSettings({1.0f, 0.0f, 0.1f});  // no glow: only the line itself
  // One particle at `x` (or none), as the state, no steps taken.
  const auto draw = [&](const glm::vec3* x) {
    GpuSimulation gpu(device(), scene);
    State state = initialState(scene);
    if (x) state.particles[0] = Particle{x->x, x->y, x->z, 0.0f, 0.6f, 0.0f, 0.3f, 1.0f};
    gpu.setState(state);
    return drawInColourOnlyPass(device(), gpu, scene, backdrop, lines, pass, kColor, kExtent,
                                view, 0);
  };
  for (bool own : {true, false}) {
    SCOPED_TRACE(own ? "with the scene's depth" : "without");
    lines.setSceneDepth(own);
    EXPECT_EQ(lines.sceneDepth(), own);
    const std::vector<uint8_t> empty = draw(nullptr);
    EXPECT_NE(draw(&beside), empty);
    EXPECT_EQ(draw(&behind) == empty, own);
  }
  vkDestroyRenderPass(vk, pass, nullptr);
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

// A host of a Vulkan 1.0 instance, under validation: deviceRequirements() asks the device
// with Vulkan 1.0 calls only (no message) and says which instance version Lava needs; given
// the instance's version, it and Device refuse it first, naming VkApplicationInfo::apiVersion.
TEST(EmbeddingVersions, AVulkan10InstanceIsRefusedByItsVersionWithoutAValidationMessage) {
  HostDevice host(VK_API_VERSION_1_0);
  host.clearMessages();  // the host's own set-up is not Lava's
  const DeviceRequirements asked =
      deviceRequirements(host.handles.instance, host.handles.physicalDevice);
  EXPECT_EQ(asked.instanceApiVersion, VK_API_VERSION_1_2);
  EXPECT_TRUE(asked.int64Atomics) << "lavapipe offers VK_KHR_shader_atomic_int64";
  const auto expectRefusal = [](const std::function<void()>& call) {
    try {
      call();
      ADD_FAILURE() << "a Vulkan 1.0 instance was accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), "VkApplicationInfo::apiVersion") << e.what();
      EXPECT_NE(std::string(e.what()).find("Vulkan 1.0"), std::string::npos) << e.what();
    }
  };
  expectRefusal([&] {
    deviceRequirements(host.handles.instance, host.handles.physicalDevice, nullptr,
                       VK_API_VERSION_1_0);
  });
  DeviceHandles handles = host.handles;
  handles.instanceApiVersion = VK_API_VERSION_1_0;
  expectRefusal([&] { Device device(handles); });
  for (const std::string& m : host.messages()) ADD_FAILURE() << "validation: " << m;
}

// An instance made without application info is Vulkan 1.0, which hides dynamic rendering
// from a Vulkan 1.3 device: the error must name the instance's version and what Lava needs,
// not blame the device.
TEST(EmbeddingVersions, AnInstanceOfVulkan10IsNamedAsTheProblem) {
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};  // no application info
  VkInstance instance = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateInstance(&info, nullptr, &instance), VK_SUCCESS);
  uint32_t count = 1;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  vkEnumeratePhysicalDevices(instance, &count, &physical);
  ASSERT_EQ(count, 1u);
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(physical, &properties);
  EXPECT_GE(properties.apiVersion, VK_API_VERSION_1_3) << "the pinned drivers are Vulkan 1.3+";
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queue;
  DeviceHandles handles;
  handles.instance = instance;
  handles.physicalDevice = physical;
  ASSERT_EQ(vkCreateDevice(physical, &deviceInfo, nullptr, &handles.device), VK_SUCCESS);
  vkGetDeviceQueue(handles.device, 0, 0, &handles.queue);
  try {
    Device device(handles);
    ADD_FAILURE() << "a Vulkan 1.0 instance was accepted";
  } catch (const ResourceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("instance"), std::string::npos) << what;
    EXPECT_NE(what.find("1.0"), std::string::npos) << what;
    EXPECT_NE(what.find("Vulkan 1.3"), std::string::npos) << what;
  }
  vkDestroyDevice(handles.device, nullptr);
  vkDestroyInstance(instance, nullptr);
}

}  // namespace
}  // namespace lava
