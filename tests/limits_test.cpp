// The limits test mode: the chunking, dispatch and binding logic under the limits
// other drivers report, imposed on lavapipe through the device context's copies of them.
// Every run must give the bytes of the unconstrained one (simulation) and the same image
// (drawing, split into the same chunks).
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "lava/lava.h"
#include "lava/validation.h"
#include "shared.h"
#include "vulkan/commands.h"
#include "vulkan/device_context.h"
#include "vulkan_test.h"

namespace lava {
namespace {

// The limits Lava sizes its particle chunks by. Vendor values are representative reports
// (vulkan.gpuinfo.org, 2024-25 drivers); what matters is which of them binds.
struct Profile {
  const char* name;
  VkDeviceSize storageRange;  // maxStorageBufferRange
  uint64_t texelElements;     // maxTexelBufferElements
  uint64_t groups;            // maxComputeWorkGroupCount[0]
  VkDeviceSize allocation;    // maxMemoryAllocationSize
  uint32_t expectedPerChunk;  // particlesPerChunk() under these limits (heap permitting)
};

constexpr Profile kProfiles[] = {
    // The spec's minimums (maintenance3: 2^30 per allocation): the texel view binds.
    {"vulkan-minimum", 1u << 27, 65536, 65535, 1u << 30, 32768},
    // NVIDIA: 4 GiB - 1 of storage range, 2^27 texels, 2^31 - 1 work groups: texels bind.
    {"nvidia", 0xFFFFFFFFu, 1u << 27, 0x7FFFFFFF, 1ull << 32, 1u << 26},
    // AMD RADV: ranges of 4 GiB - 1, 65535 work groups: the dispatch binds.
    {"radv", 0xFFFFFFFFu, 0xFFFFFFFFu, 65535, 0xFFFFFFFCu, 65535u * 64},
    // Intel ANV: 1 GiB of storage range, 2^27 texels, 65535 work groups: the dispatch binds.
    {"anv", 1u << 30, 1u << 27, 65535, 1ull << 32, 65535u * 64},
    // MoltenVK (Apple silicon): 1 GiB buffers and allocations, 2^26 texels: texels bind.
    {"moltenvk", 1u << 30, 1u << 26, 1u << 30, 1u << 30, 1u << 25},
};

void PrintTo(const Profile& p, std::ostream* os) {
  *os << p.name;
}

void impose(Device& device, const Profile& p, uint64_t divisor) {
  detail::DeviceContext& c = device.context();
  c.limits.maxStorageBufferRange = static_cast<uint32_t>(p.storageRange / divisor);
  c.limits.maxTexelBufferElements = static_cast<uint32_t>(p.texelElements / divisor);
  c.limits.maxComputeWorkGroupCount[0] = static_cast<uint32_t>(p.groups / divisor);
  c.maxAllocation = std::min<VkDeviceSize>(c.maxAllocation, p.allocation / divisor);
}

class Limits : public test::VulkanTest, public ::testing::WithParamInterface<Profile> {};

TEST_P(Limits, ChunksAsTheDriverWouldAndComputesTheSameBytes) {
  const Profile& p = GetParam();
  // The arithmetic at the true values (lavapipe's 2 GiB allocation aside).
  const VkDeviceSize ownAllocation = device().context().maxAllocation;
  impose(device(), p, 1);
  if (ownAllocation >= p.allocation) {
    EXPECT_EQ(device().particlesPerChunk(), p.expectedPerChunk);
  }

  // Scaled down by a power of two until a chunk holds a few thousand particles, so that a
  // scene of every module spans several of them.
  uint64_t divisor = 1;
  while (p.expectedPerChunk / divisor > 8192) divisor *= 2;
  impose(device(), p, divisor);
  const uint32_t perChunk = device().particlesPerChunk();
  ASSERT_GE(perChunk, 1024u);
  ASSERT_LE(perChunk, 8192u);

  Scene scene = parseScene(R"(
format = 2
integrator = "velocity-verlet"
[[emitter]]
particles = 23000
rate = 9000
shape = "sphere"
[[emitter]]
particles = 7001
rate = 3000
lifetime = 0.5
shape = "box"
[[force]]
type = "vortex"
[[collider]]
type = "cone"
[[collider]]
type = "sphere"
position = [0.5, 2, 0]
)",
                           "limits");
  GpuSimulation gpu(device(), scene);
  EXPECT_GE(gpu.chunks().size(), 30001u / perChunk);
  for (const ParticleChunk& chunk : gpu.chunks()) EXPECT_LE(chunk.count, perChunk);
  CpuSimulation cpu(scene, 2);
  gpu.advance(1500);
  cpu.advance(1500);
  const Comparison c = compare(scene, gpu.state().particles, cpu.state().particles);
  EXPECT_EQ(c.equal, c.particles) << p.name << ": " << gpu.chunks().size() << " chunks of "
                                  << perChunk << ", max ULP " << c.maxUlp;
}

TEST_P(Limits, DrawsTheSameImageChunkByChunk) {
  // Both renderers, both looks, against the same frame on the unconstrained device. Where
  // the texel views are scaled below the target's splat sums (76,800 at 320x240: the minimum,
  // NVIDIA and MoltenVK profiles), the resolves read them as a storage buffer instead.
  const Profile& p = GetParam();
  Scene scene;
  scene.emitters[0].particles = 30000;
  scene.emitters[0].rate = 9000;
  std::vector<std::vector<uint8_t>> images[2];
  for (int constrained = 0; constrained < 2; ++constrained) {
    if (constrained) {
      uint64_t divisor = 1;
      while (p.expectedPerChunk / divisor > 8192) divisor *= 2;
      impose(device(), p, divisor);
    }
    GpuSimulation simulation(device(), scene);
    simulation.advance(3000);
    if (constrained) {
      EXPECT_GE(simulation.chunks().size(), 3u);
    }
    for (LookStyle style : {LookStyle::Plain, LookStyle::Lava})
      for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
        host::FrameRenderer renderer(device(), host::OffscreenTarget::kColorFormat, style);
        renderer.setLineMode(mode);
        const host::OffscreenTarget target(device(), {320, 240});
        images[constrained].push_back(
            host::renderOffscreen(device(), renderer, simulation, target, OrbitCamera{}));
      }
  }
  for (size_t i = 0; i < images[0].size(); ++i)
    EXPECT_EQ(images[0][i], images[1][i]) << p.name << ", image " << i;
}

// Texel views too small for the glow's cells as well as the splat's sums (8K's 129,600 cells
// against the spec's minimum of 65,536; here 300 cells at 320x240 against 256 texels): the
// glow's light pass and quads read the cells as storage buffers, and every frame is the
// unconstrained one. The simulation is made before the limit, so that only the drawing
// changes (at 256 texels a chunk would hold 128 particles).
class GlowCells : public test::VulkanTest {};

TEST_F(GlowCells, DrawTheSameImageWhereTexelViewsCannotHoldThem) {
  Scene scene;
  scene.emitters[0].particles = 30000;
  scene.emitters[0].rate = 9000;
  GpuSimulation simulation(device(), scene);
  simulation.advance(3000);
  const VkExtent2D extent{320, 240};
  const uint32_t cells = (extent.width / gpu::kGlowCell) * (extent.height / gpu::kGlowCell);
  std::vector<std::vector<uint8_t>> images[2];
  for (int constrained = 0; constrained < 2; ++constrained) {
    if (constrained) {
      device().context().limits.maxTexelBufferElements = 256;
      ASSERT_GT(cells, device().context().limits.maxTexelBufferElements);
    }
    for (LookStyle style : {LookStyle::Plain, LookStyle::Lava})
      for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
        host::FrameRenderer renderer(device(), host::OffscreenTarget::kColorFormat, style);
        renderer.setLineMode(mode);
        const host::OffscreenTarget target(device(), extent);
        images[constrained].push_back(
            host::renderOffscreen(device(), renderer, simulation, target, OrbitCamera{}));
      }
  }
  ASSERT_EQ(images[1].size(), 4u);
  for (size_t i = 0; i < images[0].size(); ++i)
    EXPECT_EQ(images[0][i], images[1][i]) << "image " << i;
}

INSTANTIATE_TEST_SUITE_P(Drivers, Limits, ::testing::ValuesIn(kProfiles),
                         [](const ::testing::TestParamInfo<Profile>& param) {
                           std::string name = param.param.name;
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

}  // namespace
}  // namespace lava

namespace lava {
namespace {

// Without push descriptors, each bind of a frame slot takes the next descriptor set of its
// layout; reset() (the slot's next frame) hands the same sets out again, so a run of frames
// allocates only what its first frame did.
TEST(DescriptorArena, ReusesTheSameSetsFrameAfterFrame) {
  DeviceOptions options = test::validatedOptions();
  options.pushDescriptors = false;
  Device device(options);
  const detail::DeviceContext& c = device.context();
  ASSERT_FALSE(c.pushDescriptors);
  const auto storage =
      detail::createSetLayout(c, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, VK_SHADER_STAGE_COMPUTE_BIT);
  const auto texels = detail::createSetLayout(
      c, {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      VK_SHADER_STAGE_COMPUTE_BIT);
  detail::DescriptorArena arena(c);
  std::vector<VkDescriptorSet> first;
  for (int i = 0; i < 40; ++i)  // more than one pool's sets
    first.push_back(arena.take(i % 2 ? storage.get() : texels.get()));
  EXPECT_EQ(std::set<VkDescriptorSet>(first.begin(), first.end()).size(), first.size());
  for (int frame = 0; frame < 3; ++frame) {
    arena.reset();
    for (int i = 0; i < 40; ++i)
      EXPECT_EQ(arena.take(i % 2 ? storage.get() : texels.get()), first[i]) << frame << " " << i;
  }
  for (const std::string& message : device.takeValidationMessages())
    ADD_FAILURE() << "validation: " << message;
}

}  // namespace
}  // namespace lava
