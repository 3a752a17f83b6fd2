// The lava look by image invariants on lavapipe, both renderers: a known line's colour is the
// closed form (lava_color.glsl's model, written here again in C++) blended over the scene;
// the glow lights pixels near bright lava and none far from it; 262,144 particles do not
// burn out to white; lava at rest stays visible; the splat hides what the cone hides; the
// two renderers agree; the glow's pass resolves every pixel the splat drew; the sky is its
// gradient; the flow's molten rock is brighter than its crust, has no holes, and hides behind
// the cone.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <memory>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "host/frame_renderer.h"
#include "host/offscreen.h"
#include "host/output.h"
#include "lava/lava.h"
#include "test_scenes.h"
#include "vulkan_test.h"

namespace lava {
namespace {

using host::FrameRenderer;
using host::OffscreenTarget;

constexpr VkExtent2D kSize{320, 240};
constexpr LineMode kModes[] = {LineMode::Lines, LineMode::Splat};
const char* name(LineMode mode) {
  return mode == LineMode::Lines ? "lines" : "splat";
}

// lava_color.glsl: the energy of a line per pixel (red, green, blue) and the tone map.
glm::vec3 lavaEnergy(glm::vec3 velocity, float age, float fullRed, float coolAge) {
  const float fast = std::clamp(glm::length(velocity) / fullRed, 0.0f, 1.0f);
  glm::vec2 hue = glm::mix(glm::vec2(1.0f, 0.42f), glm::vec2(1.0f, 0.16f), fast);
  const float heat = std::exp(-std::max(age, 0.0f) * (3.0f / coolAge));
  const float t = std::clamp((heat - 0.6f) / 0.4f, 0.0f, 1.0f);
  hue = glm::mix(hue, glm::vec2(1.0f, 0.6f), t * t * (3.0f - 2.0f * t));
  const glm::vec2 rg = hue * (0.06f + 0.08f * (1.0f - fast) + 1.5f * heat * heat);
  return {rg, 0.15f * rg.y * rg.y / rg.x};
}
glm::vec3 toneMap(glm::vec3 x) {
  return 1.0f - glm::pow(1.0f + x / 16.0f, glm::vec3(-16.0f));
}

class LookTest : public test::VulkanTest {
 protected:
  static Particle particle(glm::vec3 x, glm::vec3 v, float age) {
    return Particle{x.x, x.y, x.z, age, v.x, v.y, v.z, 1.0f};
  }
  static Particle unborn() { return particle(glm::vec3(0.0f), glm::vec3(0.0f), -1.0f); }

  // One lava-look frame of `particles` (set as the state of `scene`, no steps taken).
  std::vector<uint8_t> render(Scene scene, const std::vector<Particle>& particles, LineMode mode,
                              LookSettings settings = {}) {
    scene.emitters.resize(1);
    scene.emitters[0].particles = static_cast<uint32_t>(particles.size());
    GpuSimulation simulation(device(), scene);
    State state = initialState(scene);
    state.particles = particles;
    simulation.setState(state);
    return draw(simulation, mode, settings, kSize);
  }
  std::vector<uint8_t> draw(const GpuSimulation& simulation, LineMode mode,
                            const LookSettings& settings, VkExtent2D size) {
    FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Lava);
    renderer.setLineMode(mode);
    renderer.setSettings(settings);
    const OffscreenTarget target(device(), size);
    return host::renderOffscreen(device(), renderer, simulation, target, camera_);
  }

  // One lava-look frame of a flow: `particles` with their temperatures and crust flags, the
  // state of one flow emitter of `scene` (a box emitter: no crater scenery under it).
  struct Rock {
    glm::vec3 x;
    float temperature;
    bool crust;
  };
  // `sparks` (optional) are a second emitter's particles, drawn as lines over or under it.
  std::vector<uint8_t> renderRock(Scene scene, const std::vector<Rock>& rock, LineMode mode,
                                  LookSettings settings = kNoBloomSettings(),
                                  const std::vector<Particle>& sparks = {}) {
    if (!scene.flow) scene.flow.emplace();
    scene.emitters.resize(sparks.empty() ? 1 : 2);
    Emitter& e = scene.emitters[0];
    e.particles = static_cast<uint32_t>(std::max<size_t>(rock.size(), 1));
    e.flow = true;
    e.shape = Shape::Box;
    const float spacing = 0.5f * scene.flow->radius;
    e.mass = scene.flow->density * spacing * spacing * spacing;
    if (!sparks.empty()) scene.emitters[1].particles = static_cast<uint32_t>(sparks.size());
    GpuSimulation simulation(device(), scene);
    State state = initialState(scene);
    for (size_t i = 0; i < rock.size(); ++i) {
      state.particles[i] = Particle{rock[i].x.x, rock[i].x.y, rock[i].x.z, 1.0f, 0.0f, 0.0f,
                                   0.0f, e.mass};
      state.temperature[i] = rock[i].temperature;
      state.crust[i] = rock[i].crust ? 1 : 0;
    }
    for (size_t k = 0; k < sparks.size(); ++k) state.particles[e.particles + k] = sparks[k];
    simulation.setState(state);
    std::vector<uint8_t> image = draw(simulation, mode, settings, kSize);
    if (const char* dir = std::getenv("LAVA_LOOK_IMAGES")) {  // to look at what is tested
      const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
      host::writePng(std::string(dir) + "/" + info->name() + "_" + std::to_string(++images_) +
                         ".png",
                     kSize.width, kSize.height, image);
    }
    return image;
  }
  int images_ = 0;
  // One layer of a settled pool at height y: a square lattice of the rest spacing within
  // `radius` of `centre`, all at `temperature`, crust or not.
  static std::vector<Rock> layer(glm::vec3 centre, float radius, float y, float temperature,
                                 bool crust) {
    std::vector<Rock> out;
    for (const Rock& r : pool(centre, radius, radius + 1.0f))
      out.push_back({r.x + glm::vec3(0.0f, y, 0.0f), temperature, crust});
    return out;
  }
  // The pixels of the pool's interior (within `inner` of `centre` on the ground).
  std::vector<glm::ivec2> interior(glm::vec3 centre, float inner) const {
    std::vector<glm::ivec2> out;
    for (float z = -inner; z <= inner; z += 0.01f)
      for (float x = -inner; x <= inner; x += 0.01f)
        if (x * x + z * z <= inner * inner)
          out.push_back(glm::ivec2(project(centre + glm::vec3(x, 0.0f, z))));
    std::sort(out.begin(), out.end(),
              [](glm::ivec2 a, glm::ivec2 b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  // The mean colour of `image` over `pixels`.
  static glm::dvec3 mean(const std::vector<uint8_t>& image, const std::vector<glm::ivec2>& pixels) {
    glm::dvec3 sum(0.0);
    for (const glm::ivec2 p : pixels) sum += glm::dvec3(pixel(image, p));
    return sum / double(pixels.size());
  }
  static LookSettings kNoBloomSettings() { return {1.0f, 0.0f, 0.1f}; }
  // A settled pool on the ground at `centre`: a layer on a square lattice of the rest
  // spacing within `radius`; hot inside `hot`, crust beyond it.
  static std::vector<Rock> pool(glm::vec3 centre, float radius, float hot) {
    std::vector<Rock> out;
    const float s = 0.03f;
    for (float z = -radius; z <= radius; z += s)
      for (float x = -radius; x <= radius; x += s) {
        const float r = std::sqrt(x * x + z * z);
        if (r > radius) continue;
        out.push_back({centre + glm::vec3(x, 0.0f, z), r < hot ? 1400.0f : 900.0f, r >= hot});
      }
    return out;
  }
  // The ground direction from the camera through the cone's axis (test::coneScene()), and
  // across it.
  glm::vec3 awayFromCamera() const {
    return glm::normalize(-glm::vec3(camera_.eye().x, 0.0f, camera_.eye().z));
  }
  glm::vec3 besideCone() const {
    return glm::normalize(glm::cross(awayFromCamera(), glm::vec3(0.0f, 1.0f, 0.0f)));
  }
  static double luminance(glm::ivec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

  glm::vec2 project(glm::vec3 p) const {
    const glm::vec4 clip =
        glm::make_mat4(camera_.viewProj(float(kSize.width) / float(kSize.height)).m) *
        glm::vec4(p, 1.0f);
    return {(clip.x / clip.w * 0.5f + 0.5f) * float(kSize.width),
            (clip.y / clip.w * 0.5f + 0.5f) * float(kSize.height)};
  }
  static glm::ivec3 pixel(const std::vector<uint8_t>& image, glm::ivec2 p) {
    const uint8_t* c = &image[(size_t(p.y) * kSize.width + size_t(p.x)) * 4];
    return {c[0], c[1], c[2]};
  }
  // The pixel within `radius` of `at` that `image` lights most over `background`.
  static glm::ivec2 mostLit(const std::vector<uint8_t>& image,
                            const std::vector<uint8_t>& background, glm::vec2 at, int radius) {
    glm::ivec2 best(at);
    int most = -1;
    for (int y = int(at.y) - radius; y <= int(at.y) + radius; ++y)
      for (int x = int(at.x) - radius; x <= int(at.x) + radius; ++x) {
        const glm::ivec3 d = pixel(image, {x, y}) - pixel(background, {x, y});
        if (d.x + d.y + d.z > most) most = d.x + d.y + d.z, best = {x, y};
      }
    return best;
  }

  OrbitCamera camera_;
};

const glm::vec3 kSkyPoint{0.0f, 2.6f, 0.0f};  // above the horizon: only sky behind
const LookSettings kNoBloom{1.0f, 0.0f, 0.1f};

TEST_F(LookTest, KnownLineHasTheModelsColourBlendedOverTheSky) {
  // A line 0.3 * 0.8 m long (about 15 px): its pixels are background + T(E) (1 - background)
  // with E from the colour model, fresh (yellow-orange) and cooled (a dark red crust).
  Scene scene;
  scene.lineScale = 0.3f;
  const glm::vec3 v{0.8f, 0.0f, 0.0f};
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto sky = render(scene, {unborn()}, mode, kNoBloom);
    for (float age : {0.0f, 20.0f}) {
      SCOPED_TRACE("age " + std::to_string(age));
      const auto image = render(scene, {particle(kSkyPoint, v, age)}, mode, kNoBloom);
      const glm::ivec2 at = mostLit(image, sky, project(kSkyPoint + 0.5f * 0.3f * v), 2);
      const glm::vec3 bg = glm::vec3(pixel(sky, at)) / 255.0f;
      const glm::vec3 expected = bg + toneMap(lavaEnergy(v, age, 8.0f, 5.0f)) * (1.0f - bg);
      const glm::vec3 got = glm::vec3(pixel(image, at)) / 255.0f;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c] * 255.0f, expected[c] * 255.0f, 2.5f) << "channel " << c;
      if (age == 0.0f) {
        EXPECT_GT(got.r, 0.7f);  // hot: bright, yellow-orange
        EXPECT_GT(got.g / got.r, 0.5f);
      } else {
        EXPECT_LT(got.r, 0.3f);  // crust: dim, red
        EXPECT_LT(got.g / got.r, 0.7f);
        EXPECT_GT(got.r - bg.r, 0.05f);  // but still there
      }
      EXPECT_LT(got.b, got.g);
      // The sky far from the line is untouched.
      EXPECT_EQ(pixel(image, {5, 5}), pixel(sky, {5, 5}));
    }
  }
}

TEST_F(LookTest, GlowLightsPixelsNearBrightLavaButNotFarFromIt) {
  // Many fresh particles on one spot of the sky: with bloom, pixels 12 px away are lit
  // more than without; 120 px away nothing changes.
  Scene scene;
  scene.lineScale = 0.04f;
  std::vector<Particle> spot(400, particle(kSkyPoint, glm::vec3(0.5f, 0.2f, 0.0f), 0.0f));
  const glm::vec2 at = project(kSkyPoint);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto without = render(scene, spot, mode, kNoBloom);
    const auto with = render(scene, spot, mode, LookSettings{1.0f, 1.0f, 0.1f});
    for (glm::ivec2 d : {glm::ivec2(12, 0), glm::ivec2(-12, 0), glm::ivec2(0, 12)}) {
      const glm::ivec3 a = pixel(with, glm::ivec2(at) + d), b = pixel(without, glm::ivec2(at) + d);
      EXPECT_GT(a.x - b.x, 8) << "near, offset " << d.x << "," << d.y;
      EXPECT_GE(a.y, b.y);
    }
    for (glm::ivec2 d : {glm::ivec2(120, 0), glm::ivec2(-120, 0), glm::ivec2(0, 100)})
      EXPECT_EQ(pixel(with, glm::ivec2(at) + d), pixel(without, glm::ivec2(at) + d))
          << "far, offset " << d.x << "," << d.y;
  }
}

TEST_F(LookTest, DenseLavaDoesNotBurnOutToWhite) {
  // The lab handout's crater with 262,144 particles, every slot alive, at 1280x720: fewer than 1%
  // of the pixels clipped white (all channels >= 250), and the fountain bright.
  Scene scene;
  scene.emitters[0].particles = 262144;
  scene.emitters[0].rate = 262144.0f / 5.0f;
  GpuSimulation simulation(device(), scene);
  simulation.advance(scene.stepsIn(5.0));
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto image = draw(simulation, mode, LookSettings{}, {1280, 720});
    size_t white = 0, bright = 0;
    for (size_t p = 0; p < image.size(); p += 4) {
      white += std::min({image[p], image[p + 1], image[p + 2]}) >= 250;
      bright += image[p] >= 128;
    }
    const double pixels = 1280.0 * 720.0;
    EXPECT_LT(double(white) / pixels, 0.01);
    EXPECT_GT(double(bright) / pixels, 0.10);
  }
}

TEST_F(LookTest, LavaAtRestOnTheGroundStaysVisible) {
  // A cooled particle resting on the ground (no velocity: a line of zero length) is drawn
  // as a dot in both renderers; the plain look, as the graphics pipeline, draws nothing.
  Scene scene;
  const glm::vec3 x{0.8f, 0.0f, 1.2f};
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto ground = render(scene, {unborn()}, mode, kNoBloom);
    const auto image = render(scene, {particle(x, glm::vec3(0.0f), 10.0f)}, mode, kNoBloom);
    const glm::ivec2 at = mostLit(image, ground, project(x), 2);
    const glm::ivec3 d = pixel(image, at) - pixel(ground, at);
    EXPECT_GE(d.x, 15) << "red rises by " << d.x;
    EXPECT_GT(d.x, d.y);  // red crust
  }
}

TEST_F(LookTest, SplatHidesWhatTheConeHides) {
  // A particle behind the volcano's cone, seen from the camera, is drawn by neither
  // renderer (the splat tests each line's ends against the scene's depth); the same
  // particle beside the cone is.
  Scene scene = test::coneScene();
  scene.lineScale = 0.04f;
  const glm::vec3 away = awayFromCamera(), side = besideCone();
  const glm::vec3 behind = away * 2.2f + glm::vec3(0.0f, 0.3f, 0.0f);
  const glm::vec3 beside = side * 2.6f + glm::vec3(0.0f, 0.3f, 0.0f);
  const glm::vec3 v{0.6f, 0.0f, 0.3f};
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto empty = render(scene, {unborn()}, mode, kNoBloom);
    EXPECT_EQ(render(scene, {particle(behind, v, 0.0f)}, mode, kNoBloom), empty);
    EXPECT_NE(render(scene, {particle(beside, v, 0.0f)}, mode, kNoBloom), empty);
  }
}

TEST_F(LookTest, AHotPoolIsBrighterThanItsCrustedEdge) {
  // Molten rock glows; the crust around it is dark (its cracks aside): the pool's middle is
  // far brighter than its rim, in both renderers.
  const std::vector<Rock> rock = pool(glm::vec3(0.0f), 0.45f, 0.25f);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto image = renderRock(Scene{}, rock, mode);
    double middle = 0.0, rim = 0.0;
    int inside = 0, outside = 0;
    for (const Rock& r : rock) {
      const double l = luminance(pixel(image, glm::ivec2(project(r.x))));
      if (r.crust) {
        rim += l, ++outside;
      } else {
        middle += l, ++inside;
      }
    }
    middle /= inside, rim /= outside;
    EXPECT_GT(middle, 100.0) << "the molten middle's mean luminance";
    EXPECT_GT(middle, 3.0 * rim) << "middle " << middle << ", rim " << rim;
  }
}

TEST_F(LookTest, ASettledPoolHasNoHoles) {
  // Every pixel inside a settled pool, hot or crusted, is rock: none shows the ground.
  const std::vector<Rock> rock = pool(glm::vec3(0.0f), 0.45f, 0.25f);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto ground = renderRock(Scene{}, {}, mode);
    const auto image = renderRock(Scene{}, rock, mode);
    int holes = 0, checked = 0;
    for (float r = 0.0f; r < 0.4f; r += 0.01f)
      for (float a = 0.0f; a < 6.283f; a += 0.05f) {
        const glm::ivec2 at(project(glm::vec3(r * std::cos(a), 0.0f, r * std::sin(a))));
        const glm::ivec3 d = pixel(image, at) - pixel(ground, at);
        ++checked;
        if (std::abs(d.x) + std::abs(d.y) + std::abs(d.z) < 6) ++holes;
      }
    EXPECT_EQ(holes, 0) << "of " << checked << " points inside the pool";
  }
}

TEST_F(LookTest, ASettledPoolIsOneContinuousSurface) {
  // A settled pool two layers deep, all liquid at one temperature, seen from 1.2 m (a particle
  // about 8 pixels across): the particles merge into one smooth surface, with no disc edges or
  // bumps. The mean luminance step between neighbouring pixels of its interior stays under a
  // display step and a half; discs, or spheres left unfiltered, make steps of several.
  camera_.target = {0.0f, 0.0f, 0.0f};
  camera_.distance = 1.2f;
  camera_.pitch = 0.5f;
  std::vector<Rock> rock = layer(glm::vec3(0.0f), 0.45f, 0.0f, 1300.0f, false);
  const std::vector<Rock> top = layer(glm::vec3(0.015f, 0.0f, 0.015f), 0.43f, 0.03f, 1300.0f, false);
  rock.insert(rock.end(), top.begin(), top.end());
  const std::vector<glm::ivec2> inside = interior(glm::vec3(0.0f), 0.3f);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto image = renderRock(Scene{}, rock, mode);
    double steps = 0.0;
    for (const glm::ivec2 p : inside)
      steps += std::abs(luminance(pixel(image, p + glm::ivec2(1, 0))) - luminance(pixel(image, p))) +
               std::abs(luminance(pixel(image, p + glm::ivec2(0, 1))) - luminance(pixel(image, p)));
    steps /= 2.0 * double(inside.size());
    EXPECT_GT(luminance(glm::ivec3(mean(image, inside))), 60.0) << "the pool glows";
    EXPECT_LT(steps, 1.5) << "mean luminance step between neighbours over " << inside.size()
                          << " pixels";
  }
}

TEST_F(LookTest, HotLiquidIsBrighterAndYellowerThanLiquidNearTheSolidus) {
  // The emission follows the temperature (blackbody.glsl): liquid at the eruption's 1,400 K
  // outshines liquid 50 K above the 1,000 K solidus, and is yellower (more green to its red).
  const std::vector<glm::ivec2> inside = interior(glm::vec3(0.0f), 0.3f);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const glm::dvec3 hot =
        mean(renderRock(Scene{}, layer(glm::vec3(0.0f), 0.45f, 0.0f, 1400.0f, false), mode), inside);
    const glm::dvec3 cool =
        mean(renderRock(Scene{}, layer(glm::vec3(0.0f), 0.45f, 0.0f, 1050.0f, false), mode), inside);
    EXPECT_GT(luminance(glm::ivec3(hot)), 2.0 * luminance(glm::ivec3(cool)))
        << "hot " << hot.x << "," << hot.y << "; cool " << cool.x << "," << cool.y;
    EXPECT_GT(hot.y / hot.x, cool.y / cool.x + 0.2) << "green to red";
    EXPECT_GT(cool.x, 2.0 * cool.y) << "near the solidus: red";
  }
}

TEST_F(LookTest, CrustIsDarkAndItsCracksShowTheLiquidBeneath) {
  // Crust is darker than any liquid. A thin crust over hot liquid shows bright cracks where
  // the same crust over cold crust shows none; crust near the ambient temperature is rock.
  const std::vector<glm::ivec2> inside = interior(glm::vec3(0.0f), 0.3f);
  const auto over = [](float beneath, bool crust) {
    std::vector<Rock> rock = layer(glm::vec3(0.0f), 0.45f, 0.0f, beneath, crust);
    const std::vector<Rock> skin = layer(glm::vec3(0.0f), 0.45f, 0.03f, 950.0f, true);
    rock.insert(rock.end(), skin.begin(), skin.end());
    return rock;
  };
  const auto bright = [&](const std::vector<uint8_t>& image) {
    int n = 0;
    for (const glm::ivec2 p : inside) n += luminance(pixel(image, p)) > 60.0;
    return n;
  };
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto liquid = renderRock(Scene{}, layer(glm::vec3(0.0f), 0.45f, 0.0f, 1050.0f, false), mode);
    const auto crust = renderRock(Scene{}, over(600.0f, true), mode);
    const auto cracked = renderRock(Scene{}, over(1400.0f, false), mode);
    const auto cold = renderRock(Scene{}, layer(glm::vec3(0.0f), 0.45f, 0.0f, 300.0f, true), mode);
    const double l = luminance(glm::ivec3(mean(liquid, inside)));
    const double c = luminance(glm::ivec3(mean(crust, inside)));
    EXPECT_LT(c, 0.6 * l) << "crust " << c << ", liquid near the solidus " << l;
    EXPECT_EQ(bright(crust), 0) << "crust over crust: no bright cracks";
    const int cracks = bright(cracked);
    EXPECT_GT(cracks, int(inside.size() / 20)) << "bright crack pixels of " << inside.size();
    EXPECT_LT(cracks, int(inside.size() / 2)) << "cracks, not a molten pool";
    const glm::dvec3 rock = mean(cold, inside);
    EXPECT_LT(luminance(glm::ivec3(rock)), 25.0) << "cold crust is dark rock";
    EXPECT_LT(rock.x, 1.6 * rock.z + 3.0) << "grey, not glowing red";
  }
}

TEST_F(LookTest, HotRockLightsTheGroundBesideIt) {
  // The hot pool's light reaches the ground around it through the glow; the same pool
  // cooled to crust lights nothing there.
  const glm::vec3 centre(0.0f);
  std::vector<glm::ivec2> ring;
  for (float a = 0.0f; a < 6.283f; a += 0.02f)
    for (float r : {0.55f, 0.65f})
      ring.push_back(glm::ivec2(project(centre + r * glm::vec3(std::cos(a), 0.0f, std::sin(a)))));
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto hot = renderRock(Scene{}, layer(centre, 0.45f, 0.0f, 1400.0f, false), mode,
                                LookSettings{});
    const auto cooled = renderRock(Scene{}, layer(centre, 0.45f, 0.0f, 500.0f, true), mode,
                                   LookSettings{});
    const glm::dvec3 lit = mean(hot, ring), dark = mean(cooled, ring);
    EXPECT_GT(lit.x, dark.x + 10.0) << "red beside the pool: hot " << lit.x << ", cooled "
                                    << dark.x;
  }
}

TEST_F(LookTest, SparksInFrontOfTheRockAreDrawnOverIt) {
  // A fresh spark between the camera and a molten pool is drawn over the pool, in both
  // renderers; the rock is the same in both.
  const std::vector<Rock> rock = layer(glm::vec3(0.0f), 0.45f, 0.0f, 1100.0f, false);
  const glm::vec3 eye(camera_.eye().x, camera_.eye().y, camera_.eye().z);
  const glm::vec3 x = glm::mix(glm::vec3(0.0f), eye, 0.3f);
  const Particle spark = particle(x, glm::vec3(0.0f, 0.0f, 0.0f), 0.0f);
  std::vector<uint8_t> images[2];
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto without = renderRock(Scene{}, rock, mode);
    images[mode == LineMode::Splat] = without;
    const auto with = renderRock(Scene{}, rock, mode, kNoBloomSettings(), {spark});
    const glm::ivec2 at = mostLit(with, without, project(x), 2);
    EXPECT_GT(luminance(pixel(with, at)), luminance(pixel(without, at)) + 20.0);
  }
  EXPECT_TRUE(images[0] == images[1]) << "the surface is one pass, the same in both renderers";
}

TEST_F(LookTest, RockHidesSparksBehindIt) {
  // A cube of molten rock 30 cm a side, floating, and a spark behind it on the camera's line
  // through its centre: neither renderer draws the spark; the same spark beside it, both do.
  std::vector<Rock> cube;
  for (int k = 0; k < 10; ++k) {
    const std::vector<Rock> slice =
        layer(glm::vec3(0.0f, 0.165f, 0.0f), 0.15f, 0.03f * float(k), 1200.0f, false);
    for (const Rock& r : slice)
      if (std::abs(r.x.x) <= 0.15f && std::abs(r.x.z) <= 0.15f) cube.push_back(r);
  }
  const glm::vec3 eye(camera_.eye().x, camera_.eye().y, camera_.eye().z);
  const glm::vec3 centre(0.0f, 0.3f, 0.0f);
  const glm::vec3 behind = centre + 0.35f * glm::normalize(centre - eye);
  const glm::vec3 beside = behind + 0.6f * besideCone();
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto alone = renderRock(Scene{}, cube, mode);
    const auto hidden = renderRock(Scene{}, cube, mode, kNoBloomSettings(),
                                   {particle(behind, glm::vec3(0.0f), 0.0f)});
    const auto shown = renderRock(Scene{}, cube, mode, kNoBloomSettings(),
                                  {particle(beside, glm::vec3(0.0f), 0.0f)});
    EXPECT_TRUE(hidden == alone) << "a spark behind the rock is drawn";
    EXPECT_FALSE(shown == alone) << "a spark beside the rock is not drawn";
  }
}

TEST_F(LookTest, TheConeHidesRockBehindIt) {
  // A molten pool behind the volcano's cone, seen from the camera, is hidden by it in both
  // renderers; the same pool beside the cone is drawn.
  const Scene scene = test::coneScene();
  const glm::vec3 away = awayFromCamera(), side = besideCone();
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    const auto empty = renderRock(scene, {}, mode);
    EXPECT_TRUE(renderRock(scene, pool(away * 2.3f, 0.15f, 0.1f), mode) == empty);
    EXPECT_FALSE(renderRock(scene, pool(side * 2.6f, 0.15f, 0.1f), mode) == empty);
  }
}

TEST_F(LookTest, LinesAndSplatAgree) {
  // The default scene after 3 s: the two renderers add the same light over the backdrop,
  // in total and block by block (16 x 16 pixels), up to how each samples a line.
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(3000);
  const auto lines = draw(simulation, LineMode::Lines, LookSettings{}, kSize);
  const auto splat = draw(simulation, LineMode::Splat, LookSettings{}, kSize);
  State empty = simulation.state();
  for (Particle& p : empty.particles) p.age = -1.0f;
  GpuSimulation none(device(), Scene{});
  none.setState(empty);
  const auto backdrop = draw(none, LineMode::Lines, LookSettings{}, kSize);
  double total[2] = {0.0, 0.0};
  double worst = 0.0;
  for (uint32_t by = 0; by < kSize.height; by += 16)
    for (uint32_t bx = 0; bx < kSize.width; bx += 16)
      for (int c = 0; c < 3; ++c) {
        double a = 0.0, b = 0.0;
        for (uint32_t y = by; y < by + 16; ++y)
          for (uint32_t x = bx; x < bx + 16; ++x) {
            const size_t i = (size_t(y) * kSize.width + x) * 4 + c;
            a += lines[i] - backdrop[i];
            b += splat[i] - backdrop[i];
          }
        total[0] += a;
        total[1] += b;
        worst = std::max(worst, std::abs(a - b) / 256.0);
      }
  ASSERT_GT(total[0], 256.0 * 40.0) << "the lines add light";
  EXPECT_LT(worst, 8.0) << "the largest difference of a block's mean (of 255)";
  EXPECT_NEAR(total[1] / total[0], 1.0, 0.05);
}

TEST_F(LookTest, SplatSumsStopAtTheirCapInsteadOfWrapping) {
  // Just enough identical lines that a pixel's red sum passes 2^16 (its 16 bits): without
  // the cap it would wrap to a dim red; with it the pixel stays saturated, as the graphics
  // pipeline draws it. Across the screen and steep (where two pixels one above the other
  // share a 64-bit atomic, each half capped on its own: both rows checked).
  Scene scene;
  scene.lineScale = 0.3f;
  for (const glm::vec3 v : {glm::vec3(0.8f, 0.0f, 0.0f), glm::vec3(0.0f, 0.8f, 0.0f)}) {
    SCOPED_TRACE(v.x > 0.0f ? "across" : "steep");
    const float red = lavaEnergy(v, 0.0f, 8.0f, 5.0f).r;
    const uint32_t perLine = uint32_t(red * 128.0f + 0.5f);  // kSplatScale
    const uint32_t n = 65536 / perLine + 1;
    ASSERT_LT((n * perLine) % 65536, perLine) << "the wrapped sum would be below one line's";
    const std::vector<Particle> lines(n, particle(kSkyPoint, v, 0.0f));
    const auto splat = render(scene, lines, LineMode::Splat, kNoBloom);
    const auto drawn = render(scene, lines, LineMode::Lines, kNoBloom);
    const glm::ivec2 at(project(kSkyPoint + 0.5f * 0.3f * v));
    for (const glm::ivec2 p : {at, at + glm::ivec2(v.x > 0.0f ? 1 : 0, v.x > 0.0f ? 0 : 1)}) {
      EXPECT_GE(pixel(splat, p).x, 250) << n << " lines, pixel " << p.x << ", " << p.y;
      // The pipeline samples a steep line's column by its own rule: compared across only.
      if (v.x > 0.0f) {
        EXPECT_NEAR(pixel(splat, p).x, pixel(drawn, p).x, 6);
      }
    }
  }
}

TEST_F(LookTest, GlowQuadsResolveEverySplatPixel) {
  // With the glow on, the splat's sums are resolved by the glow's quads in their pass: the
  // light pass lists the quads over every resolve tile the splat marked, lit or not. Where
  // nothing glows (a threshold no cell reaches) that pass must draw the resolve's own image;
  // with the glow, it may only add light.
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(3000);
  const auto resolved = draw(simulation, LineMode::Splat, kNoBloom, kSize);
  const auto dark = draw(simulation, LineMode::Splat, LookSettings{1.0f, 1.0f, 16.0f}, kSize);
  const auto glowing = draw(simulation, LineMode::Splat, LookSettings{}, kSize);
  ASSERT_EQ(dark.size(), resolved.size());
  size_t differ = 0, darker = 0, brighter = 0;
  for (size_t i = 0; i < resolved.size(); ++i) {
    differ += dark[i] != resolved[i];
    darker += glowing[i] < resolved[i];
    brighter += glowing[i] > resolved[i];
  }
  EXPECT_EQ(differ, 0u) << "bytes where the glow's pass, nothing glowing, differs from the resolve";
  EXPECT_EQ(darker, 0u) << "pixels the glow's pass left darker than the resolve";
  EXPECT_GT(brighter, 1000u) << "the glow adds light";
}

TEST_F(LookTest, SkyIsTheNightGradientWithinADisplayStep) {
  // sky.vert colours the sky in bands, at their edges only: every pixel of the top 30% of
  // the frame (all sky in the default view) is still the gradient's colour at its height,
  // a night blue at the top warming into the haze, within one display step (rounding).
  const auto image = render(Scene{}, {unborn()}, LineMode::Lines, kNoBloom);
  const glm::vec3 zenith{0.0015f, 0.0018f, 0.006f}, haze{0.030f, 0.011f, 0.006f};
  int worst = 0;
  for (uint32_t y = 0; y < kSize.height * 3 / 10; ++y) {
    const float height = 1.0f - (float(y) + 0.5f) / float(kSize.height);  // 1 at the top
    const float t = std::clamp((height - 0.25f) / 0.75f, 0.0f, 1.0f);
    const glm::vec3 sky = glm::mix(haze, zenith, t * t * (3.0f - 2.0f * t));
    const glm::ivec3 expected(glm::round(glm::pow(toneMap(sky), glm::vec3(1.0f / 2.2f)) * 255.0f));
    for (uint32_t x : {0u, kSize.width / 2, kSize.width - 1}) {
      const glm::ivec3 d = glm::abs(pixel(image, {int(x), int(y)}) - expected);
      worst = std::max({worst, d.x, d.y, d.z});
    }
  }
  EXPECT_LE(worst, 1) << "display steps between the sky and its gradient";
  const glm::ivec3 top = pixel(image, {0, 0}), low = pixel(image, {0, int(kSize.height) * 3 / 10});
  EXPECT_GT(top.z, top.x) << "night blue at the top";
  EXPECT_GT(low.x, top.x) << "warmer towards the horizon";
}

TEST_F(LookTest, CachedBackdropDrawsTheSameImage) {
  // The lava look's backdrop is cached and copied as the plain one is: the second frame of
  // an unchanged view looks exactly like the first.
  GpuSimulation simulation(device(), Scene{});
  simulation.advance(2000);
  for (LineMode mode : kModes) {
    SCOPED_TRACE(name(mode));
    FrameRenderer renderer(device(), OffscreenTarget::kColorFormat, LookStyle::Lava);
    renderer.setLineMode(mode);
    const OffscreenTarget target(device(), kSize);
    test::expectTheBackdropCached(device(), renderer, simulation, target, camera_);
    // Switching the look redraws the backdrop.
    renderer.setStyle(LookStyle::Plain);
    host::renderOffscreen(device(), renderer, simulation, target, camera_);
    EXPECT_FALSE(renderer.backdropReused());
  }
}

TEST_F(LookTest, SettingsOutOfRangeAreRefusedByName) {
  FrameRenderer renderer(device(), OffscreenTarget::kColorFormat);
  EXPECT_THROW(renderer.setSettings({0.0f, 1.0f, 0.1f}), InvalidArgument);
  EXPECT_THROW(renderer.setSettings({1.0f, 5.0f, 0.1f}), InvalidArgument);
  EXPECT_THROW(renderer.setSettings({1.0f, 1.0f, -1.0f}), InvalidArgument);
  EXPECT_THROW(renderer.setSettings({std::nanf(""), 1.0f, 0.1f}), InvalidArgument);
  try {
    renderer.setSettings({1.0f, 9.0f, 0.1f});
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("bloom"), std::string::npos) << e.what();
  }
  renderer.setSettings({2.0f, 0.5f, 0.2f});
  EXPECT_EQ(renderer.settings().exposure, 2.0f);
}

}  // namespace
}  // namespace lava
