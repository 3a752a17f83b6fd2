// A host application that embeds Lava: its own instance, device, queue, command buffers,
// colour and depth images (Lava creates none of them); Lava's simulation, backdrop, lines
// (the graphics pipeline and the splat, tested against the depth) and glow recorded into
// them by the frame recipe of docs/library.md, submitted on its own queue. It then reads
// the state back, checks it against Lava's CPU reference bit for bit, checks that the lava
// lit its image, and exits 0 when both hold with no validation message. It links Lava::lava
// alone; the host's own Vulkan is examples/common/vulkan_host.h.
//
//   cmake -S examples/embed -B embed -DCMAKE_PREFIX_PATH=<where Lava is installed>
//   cmake --build embed && ./embed/lava_embed
#include <lava/lava.h>
#include <vulkan/vulkan.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "vulkan_host.h"  // the host's instance, device, images, frames (examples/common)

namespace {

constexpr int kFrames = 60;  // the frames the host draws

using vkhost::check;
using vkhost::imageBarrier;

// The host's frame images, and the transitions the frame recipe makes between Lava's calls.
struct Frame {
  VkExtent2D extent;
  vkhost::Image color;  // read back at the end: VK_IMAGE_USAGE_TRANSFER_SRC_BIT
  vkhost::Image depth;  // sampled by the splat: VK_IMAGE_USAGE_SAMPLED_BIT

  Frame(const lava::DeviceHandles& host, VkExtent2D size, VkFormat colorFormat,
        VkFormat depthFormat)
      : extent(size),
        color(host, size, colorFormat,
              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
              VK_IMAGE_ASPECT_COLOR_BIT),
        depth(host, size, depthFormat,
              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
              VK_IMAGE_ASPECT_DEPTH_BIT) {}

  // Colour and depth writable. WAR: the last frame's passes, splat and copy read them.
  void toAttachments(VkCommandBuffer cmd) const {
    imageBarrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    imageBarrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            0, kTests,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  }
  // After the backdrop's pass. RAW: the second pass loads the colour; the splat samples the
  // depth (read-only from here), the lines test against it.
  void depthReadOnly(VkCommandBuffer cmd) const {
    imageBarrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    imageBarrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, kTests,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            kTests | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  }
  // `load`: the second pass, over the first's colour, depth read-only; else both cleared.
  void beginRendering(VkCommandBuffer cmd, bool load) const {
    VkRenderingAttachmentInfo colorAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    colorAttachment.imageView = color.view;
    colorAttachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colorAttachment.loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    colorAttachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingAttachmentInfo depthAttachment = colorAttachment;
    depthAttachment.imageView = depth.view;
    depthAttachment.imageLayout = load ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
                                       : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depthAttachment.storeOp = load ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
    depthAttachment.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &colorAttachment;
    rendering.pDepthAttachment = &depthAttachment;
    vkCmdBeginRendering(cmd, &rendering);
  }
  static constexpr VkPipelineStageFlags kTests =
      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
};

// The last frame's pixels, copied into a buffer the host reads; how many the lava lit.
size_t litPixels(const vkhost::Device& host, vkhost::Frames& frames, const vkhost::Image& color,
                 VkExtent2D extent) {
  const vkhost::Readback pixels(host.handles, VkDeviceSize{extent.width} * extent.height * 4);
  VkCommandBuffer cmd = frames.begin(0);
  imageBarrier(cmd, color.image, VK_IMAGE_ASPECT_COLOR_BIT,
               VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pixels.buffer, 1,
                         &region);
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &toHost, 0, nullptr, 0, nullptr);
  frames.submit(0);
  frames.wait(0);
  const std::vector<uint8_t> bgra = pixels.read();
  size_t lit = 0;
  for (size_t i = 0; i < bgra.size(); i += 4) lit += bgra[i + 2] > 150;  // red: lava, dark backdrop
  return lit;
}

// The state, read back by Lava's blocking helper, against the CPU reference; 0 when it is
// equal bit for bit, the lava lit the image and the validation layer said nothing.
int report(const vkhost::Device& host, lava::GpuSimulation& simulation, const lava::Scene& scene,
           uint64_t steps, size_t lit) {
  const std::vector<lava::Particle> gpu = simulation.state().particles;
  lava::CpuSimulation reference(scene);
  reference.advance(steps);
  const uint64_t equal = vkhost::identicalSlots(gpu, reference.state().particles);
  std::printf(
      "embed: %d frames, %llu steps, %llu/%zu slots bit-identical to the CPU reference, "
      "%zu lit pixels, %zu validation messages\n",
      kFrames, static_cast<unsigned long long>(steps), static_cast<unsigned long long>(equal),
      gpu.size(), lit, host.messages().size());
  for (const std::string& m : host.messages())
    std::fprintf(stderr, "embed: validation: %s\n", m.c_str());
  const bool pass = equal == gpu.size() && lit > 1000 && host.messages().empty();
  std::printf("embed: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}

// What the host runs on: its log's first lines, which tell the drivers' runs apart.
void describe(const vkhost::Device& host) {
  std::printf("embed: validation layer %s\n", host.validation ? "on" : "not installed");
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(host.handles.physicalDevice, &properties);
  std::printf("embed: device %s\n", properties.deviceName);
}

int run() {
  vkhost::DeviceOptions options;
  options.name = "embed";
  options.optionalFeatures = true;  // 64-bit atomics and push descriptors, where offered
  vkhost::Device host(options);
  describe(host);
  constexpr uint32_t framesInFlight = 2;
  const VkExtent2D extent{256, 256};
  const VkFormat colorFormat = VK_FORMAT_B8G8R8A8_UNORM;  // the host's choice
  const VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
  const Frame target(host.handles, extent, colorFormat, depthFormat);

  // [setup]
  // Lava on the host's handles: it never destroys them. Frame slots: the host's fences.
  // host.handles: instance, physical device, device, queue family, queue and the optional
  // features the host enabled (examples/common/vulkan_host.h makes them).
  lava::DeviceHandles handles = host.handles;
  handles.framesInFlight = framesInFlight;
  lava::Device device(handles);

  // The lava crater (5,000 slots), as Lava installs it, four times as busy.
  lava::Scene scene = lava::loadScene(std::string(LAVA_SCENES_DIR) + "/crater.toml");
  scene.emitters[0].rate = 4000.0;
  lava::GpuSimulation simulation(device, scene);
  lava::Backdrop backdrop(device, {colorFormat, depthFormat});
  lava::LineRenderer lines(device, {colorFormat, depthFormat});
  lines.setExtent(extent);
  lava::OrbitCamera camera;
  const lava::View view{camera.viewProj(1.0f), extent, camera.eye()};  // what is drawn, where
  // [setup]
  // A command buffer and a fence a frame in flight; gone (the device idle) before Lava's.
  vkhost::Frames frames(host.handles, framesInFlight);

  uint64_t steps = 0;
  for (int frame = 0; frame < kFrames; ++frame) {
    const uint32_t slot = frame % framesInFlight;  // the index of the fence that guards it
    VkCommandBuffer cmd = frames.begin(slot);      // once the slot's last frame has finished
    const uint32_t stepsThisFrame = 10 + frame % 7;  // as a variable frame time would give
    steps += stepsThisFrame;
    lines.setMode(frame % 2 ? lava::LineMode::Splat : lava::LineMode::Lines);  // both ways
    // [frame]
    simulation.update(slot, stepsThisFrame);   // CPU: plan the births, stage the schedule
    simulation.recordSimulate(cmd, slot);      // compute: the steps
    target.toAttachments(cmd);                 // host: colour and depth writable
    target.beginRendering(cmd, false);         // clear both
    backdrop.recordDraw(cmd, view, scene);     // ground and solids, writing depth
    vkCmdEndRendering(cmd);
    target.depthReadOnly(cmd);                 // host: DEPTH_STENCIL_READ_ONLY_OPTIMAL
    lines.recordPrepare(cmd, slot, simulation, view, target.depth.view);  // compute: splat, glow
    target.beginRendering(cmd, true);          // load colour; depth read-only
    lines.recordDraw(cmd, slot, simulation, view);  // lines or the splat's sums, glow
    vkCmdEndRendering(cmd);
    // [frame]
    frames.submit(slot);
  }
  check(vkDeviceWaitIdle(host.handles.device), "vkDeviceWaitIdle");
  return report(host, simulation, scene, steps, litPixels(host, frames, target.color, extent));
}

}  // namespace

int main() {
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 1;
  }
}
