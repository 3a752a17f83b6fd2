// The line renderer by image invariants on lavapipe: a known particle's line is lit with
// the expected color, the sky stays the clear color, unborn slots draw nothing, color moves
// toward red with speed and darkens with age.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "lava/lava.h"
#include "shared.h"
#include "vulkan_test.h"

namespace lava {
namespace {

using host::FrameRenderer;
using host::OffscreenTarget;

constexpr VkExtent2D kSize{320, 240};

class RenderTest : public test::VulkanTest {
 protected:
  // Renders `particles` (set as the simulation's state, no steps taken).
  std::vector<uint8_t> render(const std::vector<Particle>& particles,
                              LineMode mode = LineMode::Lines) {
    Scene scene;
    scene.emitters[0].particles = static_cast<uint32_t>(particles.size());
    scene.lineScale = 0.3f;
    GpuSimulation simulation(device(), scene);
    State state = initialState(scene);
    state.particles = particles;
    simulation.setState(state);
    return draw(simulation, mode, camera_);
  }

  // One frame of `simulation` into a fresh offscreen target.
  std::vector<uint8_t> draw(const GpuSimulation& simulation, LineMode mode,
                            const OrbitCamera& camera) {
    FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Plain);
    renderer.setLineMode(mode);
    const OffscreenTarget target(device(), kSize);
    return host::renderOffscreen(device(), renderer, simulation, target, camera);
  }

  glm::mat4 viewProj() const {
    return glm::make_mat4(camera_.viewProj(float(kSize.width) / float(kSize.height)).m);
  }
  // Where a world point lands on the target, in pixels (a pixel's centre at + 0.5).
  glm::vec2 pixelOf(glm::vec3 p) const {
    const glm::vec4 clip = viewProj() * glm::vec4(p, 1.0f);
    return (glm::vec2(clip) / clip.w * 0.5f + 0.5f) *
           glm::vec2(float(kSize.width), float(kSize.height));
  }
  // The pixel a world point lands in.
  glm::ivec2 project(glm::vec3 p) const { return glm::ivec2(pixelOf(p)); }

  // The brightest pixel (sum of RGB) within 2 pixels of `at`.
  static std::array<int, 3> brightestNear(const std::vector<uint8_t>& image, glm::ivec2 at) {
    std::array<int, 3> best{0, 0, 0};
    for (int y = at.y - 2; y <= at.y + 2; ++y)
      for (int x = at.x - 2; x <= at.x + 2; ++x) {
        const uint8_t* p = &image[(size_t(y) * kSize.width + size_t(x)) * 4];
        if (p[0] + p[1] + p[2] > best[0] + best[1] + best[2]) best = {p[0], p[1], p[2]};
      }
    return best;
  }

  static Particle particle(glm::vec3 x, glm::vec3 v, float age) {
    return Particle{x.x, x.y, x.z, age, v.x, v.y, v.z, 1.0f};
  }

  // The world point drawn at pixel `p` (as project() counts pixels), at kSkyPoint's depth.
  glm::vec3 unproject(glm::vec2 p) const;
  // A particle whose line runs from pixel `a` to pixel `b` (render()'s line scale).
  Particle lineBetween(glm::vec2 a, glm::vec2 b) const {
    const glm::vec3 x = unproject(a);
    return particle(x, (unproject(b) - x) / 0.3f, 0.0f);
  }

  // The brightest pixels of a slow (0.4 m/s) and a fast (12 m/s) line on the sky.
  std::pair<std::array<int, 3>, std::array<int, 3>> slowAndFast(LineMode mode);
  // The default scene after 3 s, drawn with `mode`.
  std::vector<uint8_t> renderDefaultScene(LineMode mode);

  OrbitCamera camera_;
};

const glm::vec3 kSkyPoint{0.0f, 2.6f, 0.0f};  // above the horizon: only the clear color behind

glm::vec3 RenderTest::unproject(glm::vec2 p) const {
  const glm::vec4 sky = viewProj() * glm::vec4(kSkyPoint, 1.0f);
  const glm::vec2 ndc = p / glm::vec2(float(kSize.width), float(kSize.height)) * 2.0f - 1.0f;
  const glm::vec4 world = glm::inverse(viewProj()) * glm::vec4(ndc * sky.w, sky.z, sky.w);
  return glm::vec3(world) / world.w;
}

std::pair<std::array<int, 3>, std::array<int, 3>> RenderTest::slowAndFast(LineMode mode) {
  const glm::vec3 slow{0.4f, 0.0f, 0.0f}, fast{12.0f, 0.0f, 0.0f};
  return {brightestNear(render({particle(kSkyPoint, slow, 0.0f)}, mode),
                        project(kSkyPoint + 0.5f * 0.3f * slow)),
          brightestNear(render({particle(kSkyPoint, fast, 0.0f)}, mode),
                        project(kSkyPoint + 0.05f * 0.3f * fast))};
}

std::vector<uint8_t> RenderTest::renderDefaultScene(LineMode mode) {
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(3000);
  return draw(simulation, mode, camera_);
}

TEST_F(RenderTest, SlowParticleLineIsOrangeOnTheSky) {
  const glm::vec3 v{0.8f, 0.0f, 0.0f};
  const auto image = render({particle(kSkyPoint, v, 0.0f)});
  const auto c = brightestNear(image, project(kSkyPoint + 0.5f * 0.3f * v));
  EXPECT_GT(c[0], 200) << c[0] << "," << c[1] << "," << c[2];
  EXPECT_GT(c[1], 80);  // orange: green about half of red
  EXPECT_LT(c[1], 170);
  EXPECT_LT(c[2], 60);
  const uint8_t* corner = &image[0];  // top-left: sky
  EXPECT_LT(corner[0] + corner[1] + corner[2], 20);
}

TEST_F(RenderTest, ColorMovesTowardRedWithSpeed) {
  const auto [a, b] = slowAndFast(LineMode::Lines);
  ASSERT_GT(a[0], 100);
  ASSERT_GT(b[0], 100);
  EXPECT_GT(double(a[1]) / a[0], 0.4);   // orange
  EXPECT_LT(double(b[1]) / b[0], 0.15);  // red
}

TEST_F(RenderTest, ColorCoolsWithAge) {
  const glm::vec3 v{0.8f, 0.0f, 0.0f};
  const glm::ivec2 at = project(kSkyPoint + 0.5f * 0.3f * v);
  const auto young = brightestNear(render({particle(kSkyPoint, v, 0.0f)}), at);
  const auto old = brightestNear(render({particle(kSkyPoint, v, 10.0f)}), at);
  EXPECT_LT(old[0], young[0] * 0.5);
}

TEST_F(RenderTest, UnbornSlotsDrawNothing) {
  std::vector<Particle> unborn(500), moved(500);
  for (size_t i = 0; i < unborn.size(); ++i) {
    const float f = float(i) / 500.0f;
    unborn[i] = particle({f - 0.5f, 1.0f + f, 0.0f}, {1.0f, 2.0f, 0.0f}, -1.0f);
    moved[i] = particle({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, -1.0f);
  }
  const auto a = render(unborn), b = render(moved);
  EXPECT_EQ(a, b);  // where an unborn slot is does not matter: nothing is drawn
  const auto c = brightestNear(a, project(kSkyPoint));
  EXPECT_LT(c[0] + c[1] + c[2], 20);
}

TEST_F(RenderTest, SplatDrawsTheSameLineInTheSameColor) {
  const glm::vec3 v{0.8f, 0.0f, 0.0f};
  const glm::ivec2 at = project(kSkyPoint + 0.5f * 0.3f * v);
  const auto reference = brightestNear(render({particle(kSkyPoint, v, 0.0f)}), at);
  const auto splat = brightestNear(render({particle(kSkyPoint, v, 0.0f)}, LineMode::Splat), at);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(splat[c], reference[c], 6) << "channel " << c;
}

TEST_F(RenderTest, SplatMovesTowardRedWithSpeedAndDrawsNoUnbornSlot) {
  const auto [a, b] = slowAndFast(LineMode::Splat);
  ASSERT_GT(a[0], 100);
  ASSERT_GT(b[0], 100);
  EXPECT_GT(double(a[1]) / a[0], 0.4);
  EXPECT_LT(double(b[1]) / b[0], 0.15);
  const glm::vec3 v{0.4f, 0.0f, 0.0f};
  std::vector<Particle> unborn(300, particle(kSkyPoint, v, -1.0f));
  EXPECT_EQ(render(unborn, LineMode::Splat),
            render({particle(kSkyPoint, v, -1.0f)}, LineMode::Splat));
}

TEST_F(RenderTest, ZeroLengthLinesDrawNothingInEitherRenderer) {
  // A particle at rest on the ground has a line shorter than a pixel: no pixel centre is
  // crossed, so neither the graphics pipeline nor the splatter draws it.
  const std::vector<Particle> resting(50, particle(kSkyPoint, glm::vec3(0.0f), 0.0f));
  const std::vector<Particle> unborn(50, particle(kSkyPoint, glm::vec3(0.0f), -1.0f));
  for (LineMode mode : {LineMode::Lines, LineMode::Splat})
    EXPECT_EQ(render(resting, mode), render(unborn, mode)) << (mode == LineMode::Splat);
}

// lines.vert clips each line to the view volume itself (no vertex may leave it, or llvmpipe
// takes its slow clipping path): a line leaving the target is drawn up to its edge along
// the same pixels, one wholly off it draws nothing, and one whose end lies behind the
// camera draws its visible part: from its start, the way the line leaves it on screen
// (projecting the end itself, through w < 0, would point the other way).
TEST_F(RenderTest, LinesLeavingTheViewAreDrawnUpToItsEdgeAndNoFurther) {
  const std::vector<uint8_t> empty = render({particle(kSkyPoint, glm::vec3(1.0f), -1.0f)});
  // The centres of the pixels a line lit (red over the scene's by more than 100).
  const auto lit = [&](const std::vector<uint8_t>& image) {
    std::vector<glm::vec2> centres;
    for (uint32_t y = 0; y < kSize.height; ++y)
      for (uint32_t x = 0; x < kSize.width; ++x) {
        const size_t i = (size_t(y) * kSize.width + x) * 4;
        if (image[i] > empty[i] + 100) centres.push_back({float(x) + 0.5f, float(y) + 0.5f});
      }
    return centres;
  };
  // Checks every lit pixel's centre lies within a pixel of the ray from `from` along `dir`
  // (none more than 1.5 behind its start); returns how many there are.
  const auto alongRay = [&](const std::vector<glm::vec2>& centres, glm::vec2 from, glm::vec2 dir,
                            const char* what) {
    dir = glm::normalize(dir);
    for (const glm::vec2 c : centres) {
      const glm::vec2 d = c - from;
      EXPECT_GT(glm::dot(d, dir), -1.5f) << what << ": pixel (" << c.x << ", " << c.y << ")";
      EXPECT_LT(std::abs(d.x * dir.y - d.y * dir.x), 1.0f)
          << what << ": pixel (" << c.x << ", " << c.y << ") off the line";
    }
    return centres.size();
  };

  // Out through the right edge and through the top: every column (row) up to the edge.
  const glm::vec2 right0{250.2f, 100.3f}, right1{1000.0f, 130.0f};
  const auto rightLit = lit(render({lineBetween(right0, right1)}));
  EXPECT_GE(alongRay(rightLit, right0, right1 - right0, "right"), size_t(kSize.width) - 251u);
  EXPECT_TRUE(std::any_of(rightLit.begin(), rightLit.end(),
                          [](glm::vec2 c) { return c.x == float(kSize.width) - 0.5f; }));
  const glm::vec2 top0{100.4f, 60.2f}, top1{70.0f, -500.0f};
  const auto topLit = lit(render({lineBetween(top0, top1)}));
  EXPECT_GE(alongRay(topLit, top0, top1 - top0, "top"), 59u);
  EXPECT_TRUE(std::any_of(topLit.begin(), topLit.end(), [](glm::vec2 c) { return c.y == 0.5f; }));

  // Wholly off the target, left of it and below it: nothing.
  EXPECT_EQ(render({lineBetween({-300.0f, 100.0f}, {-20.0f, 140.0f})}), empty);
  EXPECT_EQ(render({lineBetween({40.0f, 400.0f}, {300.0f, 260.0f})}), empty);

  // From the sky point to behind the camera, passing beside it.
  const Vec3 e = camera_.eye();
  const glm::vec3 eye{e.x, e.y, e.z};
  const glm::vec3 behind = eye + 0.5f * (eye - kSkyPoint) + glm::vec3(0.0f, 0.0f, 1.5f);
  const glm::vec2 start = pixelOf(kSkyPoint);
  const glm::vec2 toward = pixelOf(kSkyPoint + 0.02f * (behind - kSkyPoint)) - start;
  const auto behindLit = lit(render({particle(kSkyPoint, (behind - kSkyPoint) / 0.3f, 0.0f)}));
  EXPECT_GE(alongRay(behindLit, start, toward, "behind the camera"), 120u);
  EXPECT_TRUE(std::any_of(behindLit.begin(), behindLit.end(),
                          [&](glm::vec2 c) { return glm::length(c - start) < 2.0f; }))
      << "the line's start at (" << start.x << ", " << start.y << ") is not drawn";
}

TEST_F(RenderTest, SplatAndPipelineLightTheSamePixels) {
  const auto lines = renderDefaultScene(LineMode::Lines);
  const auto splat = renderDefaultScene(LineMode::Splat);
  size_t litLines = 0, litSplat = 0, litBoth = 0;
  for (size_t i = 0; i < lines.size(); i += 4) {
    const bool a = lines[i] > 100, b = splat[i] > 100;
    litLines += a;
    litSplat += b;
    litBoth += a && b;
  }
  ASSERT_GT(litLines, 500u);
  // Both sample lines at pixel centres; they differ where a centre sits on a line's end
  // (about 93% agree on lavapipe).
  EXPECT_GT(double(litBoth) / double(litLines), 0.85);
  EXPECT_GT(double(litBoth) / double(litSplat), 0.85);
}

// The splat resolves only the tiles of kResolveTile^2 pixels it marked: a line that starts
// in one tile and ends in others is drawn in each of them. Each line alone (no other line
// marks the tiles it reaches), across a tile's side leftwards, across one upwards, and
// across a corner; every tile the graphics pipeline lights must be lit by the splat too.
TEST_F(RenderTest, SplatDrawsLinesAcrossResolveTiles) {
  const float t = float(gpu::kResolveTile);
  const std::array<std::pair<glm::vec2, glm::vec2>, 3> lines{{
      {{2 * t + 9.5f, 1.5f * t + 0.3f}, {2 * t - 12.5f, 1.5f * t + 2.7f}},
      {{1.5f * t + 0.4f, 2 * t + 10.5f}, {1.5f * t - 2.6f, 2 * t - 11.5f}},
      {{2 * t - 7.3f, 2 * t - 6.6f}, {2 * t + 9.2f, 2 * t + 8.1f}},
  }};
  const uint32_t across = (kSize.width + gpu::kResolveTile - 1) / gpu::kResolveTile;
  const auto litTiles = [&](const std::vector<uint8_t>& image) {
    std::vector<int> lit(size_t(across) *
                         ((kSize.height + gpu::kResolveTile - 1) / gpu::kResolveTile));
    for (uint32_t y = 0; y < kSize.height; ++y)
      for (uint32_t x = 0; x < kSize.width; ++x)
        if (image[(size_t(y) * kSize.width + x) * 4] > 100)
          ++lit[(y / gpu::kResolveTile) * across + x / gpu::kResolveTile];
    return lit;
  };
  for (const auto& [a, b] : lines) {
    const std::vector<int> pipeline = litTiles(render({lineBetween(a, b)}, LineMode::Lines));
    const std::vector<int> splat = litTiles(render({lineBetween(a, b)}, LineMode::Splat));
    size_t reached = 0;
    for (size_t tile = 0; tile < pipeline.size(); ++tile) {
      if (pipeline[tile] < 3) continue;
      ++reached;
      EXPECT_GT(splat[tile], 0) << "tile " << tile << " of the line from (" << a.x << ", " << a.y
                                << ") to (" << b.x << ", " << b.y << ")";
    }
    EXPECT_GE(reached, 2u) << "the line from (" << a.x << ", " << a.y << ") crosses no tile";
  }
}

TEST_F(RenderTest, CachedGroundDrawsTheSameImage) {
  // The second frame of an unchanged view copies the ground from the renderer's cache; it
  // must look exactly like drawing it. A new view draws again, then caches again.
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2000);
  for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
    FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Plain);
    renderer.setLineMode(mode);
    const OffscreenTarget target(device(), kSize);
    const auto drawn =
        test::expectTheBackdropCached(device(), renderer, simulation, target, camera_);
    OrbitCamera turned = camera_;
    turned.yaw += 0.5f;
    const auto turnedDrawn =
        host::renderOffscreen(device(), renderer, simulation, target, turned);
    EXPECT_FALSE(renderer.backdropReused());
    EXPECT_NE(turnedDrawn, drawn);
    const auto turnedCopied =
        host::renderOffscreen(device(), renderer, simulation, target, turned);
    EXPECT_TRUE(renderer.backdropReused());
    EXPECT_EQ(turnedDrawn, turnedCopied);
  }
}

TEST_F(RenderTest, CachedBackdropIsRedrawnWhenTheCraterOrTheSizeChanges) {
  // Not only a camera move: a new crater (the emitter moved or widened, a collider added)
  // and a new target size each draw the backdrop again, and the copy that follows matches.
  Scene scene;
  GpuSimulation simulation(device(), scene);
  simulation.advance(500);
  FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Plain);
  const OffscreenTarget target(device(), kSize);
  host::renderOffscreen(device(), renderer, simulation, target, camera_);
  host::renderOffscreen(device(), renderer, simulation, target, camera_);
  ASSERT_TRUE(renderer.backdropReused());
  const auto before = host::renderOffscreen(device(), renderer, simulation, target, camera_);
  scene.emitters[0].radius = 0.4f;
  simulation.setScene(scene);
  const auto wider = host::renderOffscreen(device(), renderer, simulation, target, camera_);
  EXPECT_FALSE(renderer.backdropReused());
  EXPECT_NE(wider, before) << "a wider crater looks different";
  EXPECT_EQ(host::renderOffscreen(device(), renderer, simulation, target, camera_), wider);
  EXPECT_TRUE(renderer.backdropReused());
  Collider box;
  box.type = ColliderType::Box;
  box.position = {1.5f, 0.5f, 0.0f};
  scene.colliders = {box};
  GpuSimulation withBox(device(), scene);
  withBox.setState(simulation.state());
  host::renderOffscreen(device(), renderer, withBox, target, camera_);
  EXPECT_FALSE(renderer.backdropReused());
  const OffscreenTarget smaller(device(), {200, 150});
  host::renderOffscreen(device(), renderer, withBox, smaller, camera_);
  EXPECT_FALSE(renderer.backdropReused());
  host::renderOffscreen(device(), renderer, withBox, smaller, camera_);
  EXPECT_TRUE(renderer.backdropReused());
}

// With 64-bit buffer atomics the splat adds a steep line's pixels two at a time (one above
// the other in one word of the sums): the same sums, so the same images as one pixel per
// atomic, in both looks, for the default scene and for steep lines piled past the sums' cap
// (where each half of a word is taken back on its own).
TEST_F(RenderTest, SplatPairsOfPixelsDrawTheSameImagesAsSinglePixels) {
  DeviceOptions options = test::validatedOptions();
  options.int64Atomics = true;  // whatever LAVA_DEVICE_PROFILE says
  Device pairs(options);
  ASSERT_TRUE(pairs.handles().int64Atomics)
      << "this device offers no 64-bit buffer atomics: run this test where it does (lavapipe)";
  options.int64Atomics = false;
  Device single(options);
  ASSERT_FALSE(single.handles().int64Atomics);
  Scene pile;
  pile.emitters[0].particles = 5000;
  pile.lineScale = 0.3f;
  State piled = initialState(pile);
  for (size_t i = 0; i < piled.particles.size(); ++i)  // steep, on even and odd rows
    piled.particles[i] = particle(kSkyPoint + glm::vec3(0.0f, 0.004f * float(i % 3), 0.0f),
                                  {0.1f, 3.0f, 0.0f}, 0.0f);
  const auto draw = [&](Device& on, LookStyle style, bool piledUp) {
    const Scene scene = piledUp ? pile : Scene{};
    GpuSimulation simulation(on, scene);
    if (piledUp)
      simulation.setState(piled);
    else
      simulation.advance(3000);
    FrameRenderer renderer(on, OffscreenTarget::kColorFormat, style);
    renderer.setLineMode(LineMode::Splat);
    const OffscreenTarget target(on, kSize);
    return host::renderOffscreen(on, renderer, simulation, target, camera_);
  };
  for (LookStyle style : {LookStyle::Plain, LookStyle::Lava})
    for (bool piledUp : {false, true}) {
      SCOPED_TRACE(std::string(style == LookStyle::Lava ? "lava" : "plain") +
                   (piledUp ? ", piled up" : ", default scene"));
      const auto paired = draw(pairs, style, piledUp);
      EXPECT_EQ(paired, draw(single, style, piledUp));
      size_t lit = 0;
      for (size_t i = 0; i < paired.size(); i += 4) lit += paired[i] > 100;
      EXPECT_GT(lit, 20u);
    }
  for (Device* d : {&pairs, &single})
    for (const std::string& message : d->takeValidationMessages())
      ADD_FAILURE() << "validation: " << message;
}

TEST_F(RenderTest, SplatSaturatesInsteadOfBleedingGreenIntoRed) {
  // 5,000 identical lines on the same pixels: far past what one pixel of the fixed-point
  // sums holds (red stops at kSplatFull). The splat must show what the graphics pipeline
  // shows, a saturated colour of the same hue (LookTest checks the wrap itself).
  for (LookStyle style : {LookStyle::Plain, LookStyle::Lava}) {
    SCOPED_TRACE(style == LookStyle::Lava ? "lava" : "plain");
    Scene scene;
    scene.emitters[0].particles = 5000;
    scene.lineScale = 0.3f;
    GpuSimulation simulation(device(), scene);
    State state = initialState(scene);
    for (Particle& p : state.particles) p = particle(kSkyPoint, {0.8f, 0.0f, 0.0f}, 0.0f);
    simulation.setState(state);
    std::vector<uint8_t> images[2];
    for (int splat = 0; splat < 2; ++splat) {
      FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, style);
      renderer.setLineMode(splat ? LineMode::Splat : LineMode::Lines);
      renderer.setSettings({1.0f, 0.0f, 0.1f});
      const OffscreenTarget target(device(), kSize);
      images[splat] = host::renderOffscreen(device(), renderer, simulation, target, camera_);
    }
    const auto lines =
        brightestNear(images[0], project(kSkyPoint + 0.5f * 0.3f * glm::vec3(0.8f, 0, 0)));
    const auto splat =
        brightestNear(images[1], project(kSkyPoint + 0.5f * 0.3f * glm::vec3(0.8f, 0, 0)));
    // (8-bit blending of 5,000 lines stalls a few steps short of 255 where each adds less
    // than half a step; the splat's one tone map of the sum does not.)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(splat[c], lines[c], 8) << "channel " << c;
    EXPECT_GE(splat[0], 250);
    EXPECT_GE(splat[1], style == LookStyle::Lava ? 250 : 140) << "green neither lost nor wrapped";
  }
}

TEST_F(RenderTest, HostMemoryTargetDrawsTheSameImage) {
  // The MIT-SHM presenter renders into the X server's shared memory: a linear color image
  // over host memory must show what the usual target shows, and so must its fallback.
  ASSERT_TRUE(OffscreenTarget::hostColorSupported(device(), OffscreenTarget::kColorFormat))
      << "lavapipe can render into host memory";
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2000);
  const auto bytes = OffscreenTarget::hostBytes(device(), kSize, OffscreenTarget::kColorFormat);
  ASSERT_TRUE(bytes) << "rows packed at 320x240";
  std::unique_ptr<void, decltype(&std::free)> host(
      std::aligned_alloc(OffscreenTarget::hostImportAlignment(device()), *bytes), &std::free);
  for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
    const auto expected = draw(simulation, mode, camera_);
    FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Plain);
    renderer.setLineMode(mode);
    const OffscreenTarget inHost(device(), kSize, OffscreenTarget::kColorFormat, host.get());
    EXPECT_TRUE(inHost.inHostMemory());
    EXPECT_EQ(inHost.mappedPixels(), host.get());
    EXPECT_EQ(expected, host::renderOffscreen(device(), renderer, simulation, inHost, camera_));
    // The presenter's fallback, a usual target read back, is `expected` itself.
    const OffscreenTarget readBack(device(), kSize);
    EXPECT_FALSE(readBack.inHostMemory());
  }
}

TEST_F(RenderTest, HostWritesTheCachedBackdropIntoAHostMemoryTarget) {
  // The MIT-SHM presenter's frames live in host memory: once a slot holds a finished frame,
  // the renderer writes the cached backdrop into it from the host (read back once, in the
  // first frame that copies it, ready when that frame's slot comes round again; the lines
  // only, the splat keeps the device's copy). Each frame must equal the usual target's,
  // however stale or foreign the memory it starts from.
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2000);
  const auto bytes = OffscreenTarget::hostBytes(device(), kSize, OffscreenTarget::kColorFormat);
  ASSERT_TRUE(bytes);
  std::unique_ptr<void, decltype(&std::free)> host(
      std::aligned_alloc(OffscreenTarget::hostImportAlignment(device()), *bytes), &std::free);
  const auto frame = [&](FrameRenderer& renderer, uint32_t slot, const host::FrameTarget& target,
                         const OrbitCamera& camera) {
    device().submitNow([&](VkCommandBuffer commands) {
      renderer.record(commands, slot, simulation, target, camera);
      host::memoryBarrier(commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                          VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    });
    const auto* p = static_cast<const uint8_t*>(host.get());
    return std::vector<uint8_t>(p, p + size_t(kSize.width) * kSize.height * 4);
  };
  OrbitCamera turned = camera_;
  turned.yaw += 0.5f;
  for (LookStyle style : {LookStyle::Plain, LookStyle::Lava}) {
    for (LineMode mode : {LineMode::Lines, LineMode::Splat}) {
      SCOPED_TRACE(std::string(style == LookStyle::Lava ? "lava" : "plain") +
                   (mode == LineMode::Splat ? " splat" : " lines"));
      FrameRenderer usual(device(), OffscreenTarget::kColorFormat, style);
      usual.setLineMode(mode);
      const OffscreenTarget plainTarget(device(), kSize);
      const auto expected =
          host::renderOffscreen(device(), usual, simulation, plainTarget, camera_);
      const auto expectedTurned =
          host::renderOffscreen(device(), usual, simulation, plainTarget, turned);

      FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, style);
      renderer.setLineMode(mode);
      const OffscreenTarget inHost(device(), kSize, OffscreenTarget::kColorFormat, host.get());
      // The first frame draws the backdrop; nothing is in the memory yet to write over.
      EXPECT_EQ(frame(renderer, 0, inHost.target(), camera_), expected);
      EXPECT_FALSE(renderer.backdropReused());
      // Frames 1 and 2 copy it on the device (frame 1 also reads it back); from frame 3, in
      // frame 1's slot again, the host writes it, over memory scribbled on in between.
      for (uint32_t i = 1; i < 6; ++i) {
        std::memset(host.get(), int(0x35 * i), *bytes);
        EXPECT_EQ(frame(renderer, i % 2, inHost.targetWithHostColor(), camera_), expected)
            << "frame " << i;
        EXPECT_TRUE(renderer.backdropReused());
        EXPECT_EQ(renderer.backdropWrittenByHost(), i >= 3 && mode == LineMode::Lines)
            << "frame " << i;
      }
      // A new view: drawn, copied and read back anew; the host writes the new backdrop.
      EXPECT_EQ(frame(renderer, 0, inHost.targetWithHostColor(), turned), expectedTurned);
      for (uint32_t i = 1; i < 4; ++i) {
        std::memset(host.get(), int(0x35 * i), *bytes);
        EXPECT_EQ(frame(renderer, i % 2, inHost.targetWithHostColor(), turned), expectedTurned)
            << "turned, frame " << i;
        EXPECT_EQ(renderer.backdropWrittenByHost(), i >= 3 && mode == LineMode::Lines)
            << "turned, frame " << i;
      }
    }
  }
}

TEST_F(RenderTest, DefaultSceneLightsManyPixelsOrangeAndRed) {
  const auto image = renderDefaultScene(LineMode::Lines);
  size_t lava = 0;
  for (size_t i = 0; i < image.size(); i += 4)
    lava += image[i] > 120 && image[i] > 2 * image[i + 2] && image[i + 1] < image[i];
  EXPECT_GT(lava, 1000u);
}

TEST(ShmCopy, PaddedRowsLandAtTheirPitchAndThePaddingIsKept) {
  // The MIT-SHM presenter's copy into an X image whose rows are padded past width * 4.
  const uint32_t width = 3, height = 4;
  const size_t row = width * 4, pitch = row + 8;
  std::vector<uint8_t> source(row * height), image(pitch * height, 0xEE);
  for (size_t i = 0; i < source.size(); ++i) source[i] = static_cast<uint8_t>(i);
  host::copyRows(image.data(), pitch, source.data(), row, height);
  for (uint32_t y = 0; y < height; ++y) {
    for (size_t x = 0; x < row; ++x) EXPECT_EQ(image[y * pitch + x], source[y * row + x]);
    for (size_t x = row; x < pitch; ++x) EXPECT_EQ(image[y * pitch + x], 0xEE) << "padding";
  }
  std::vector<uint8_t> packed(row * height, 0);
  host::copyRows(packed.data(), row, source.data(), row, height);
  EXPECT_EQ(packed, source);
}

}  // namespace
}  // namespace lava
