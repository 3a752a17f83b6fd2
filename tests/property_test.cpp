// Random valid scenes through the whole program (`lava simulate`): every module, and the flow
// in half of them. For each: it exits 0 on both backends with the same bytes, holds no NaN,
// leaves no particle below the ground or inside a collider, and a checkpoint halfway resumed
// gives the straight run's bytes. The scenes that ever failed are kept in tests/property/ and
// run first. LAVA_PROPERTY_SCENES=N draws N scenes instead of CI's few (LAVA_PROPERTY_SEED
// picks the first seed); a failure names its seed and the TOML to keep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "cli_test.h"
#include "lava/scene.h"
#include "scene/keys.h"
#include "test_scenes.h"

namespace lava {
namespace {

using cli::lava;
using cli::readFile;
using cli::scratch;

// Colliders that never overlap each other or reach below the ground: one plane alone, or up
// to three solids two metres apart along x (the model resolves colliders one after another,
// so overlapping ones may push a particle from one into the next).
void separatedColliders(Scene& s, std::mt19937& rng) {
  auto uniform = [&](float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(rng);
  };
  s.colliders.clear();
  const uint32_t mode = uint32_t(rng() % 3);
  if (mode == 1) {
    Collider plane;
    plane.type = ColliderType::Plane;
    plane.position = {uniform(-1, 1), uniform(0.0f, 0.5f), uniform(-1, 1)};
    plane.normal = {uniform(-0.5f, 0.5f), 1.0f, uniform(-0.5f, 0.5f)};
    plane.restitution = uniform(0, 1);
    plane.friction = uniform(0, 1);
    s.colliders.push_back(plane);
  } else if (mode == 2) {
    for (float x : {-2.0f, 0.0f, 2.0f}) {
      if (rng() % 4 == 0) continue;
      Collider c;
      c.type = static_cast<ColliderType>(1 + rng() % 3);  // sphere, box, cone
      c.restitution = uniform(0, 1);
      c.friction = uniform(0, 1);
      c.radius = uniform(0.2f, 0.8f);
      c.size = {uniform(0.1f, 0.55f), uniform(0.1f, 0.55f), uniform(0.1f, 0.55f)};
      c.baseRadius = uniform(0.3f, 0.9f);
      c.topRadius = uniform(0.0f, c.baseRadius);
      c.height = uniform(0.2f, 0.9f);
      const float lift = c.type == ColliderType::Sphere ? c.radius
                         : c.type == ColliderType::Box ? c.size.y
                                                       : 0.0f;
      c.position = {x, c.type == ColliderType::Cone ? 0.0f : lift + uniform(0.0f, 1.0f),
                    uniform(-0.1f, 0.1f)};
      s.colliders.push_back(c);
    }
  }
}

Scene propertyScene(uint32_t seed) {
  std::mt19937 rng(seed);
  Scene s = test::randomModuleScene(rng);
  separatedColliders(s, rng);
  for (Emitter& e : s.emitters) e.particles = std::min<uint32_t>(e.particles, 2500);
  if (rng() % 2 == 0) {  // the flow: its last emitter, a few hundred particles of rock
    auto uniform = [&](float lo, float hi) {
      return std::uniform_real_distribution<float>(lo, hi)(rng);
    };
    Flow f;
    f.radius = uniform(0.04f, 0.1f);
    f.temperature = uniform(1200.0f, 1500.0f);
    f.solidus = uniform(900.0f, f.temperature - 100.0f);
    f.viscosity = uniform(0.01f, 0.2f);
    f.viscositySolidus = uniform(f.viscosity, 10.0f);
    f.coolingAir = uniform(0.0f, 0.05f);
    f.coolingGround = uniform(0.0f, 2.0f);
    f.conduction = rng() % 2 ? uniform(0.0f, 0.001f) : 0.0f;
    f.restitution = uniform(0.0f, 0.5f);
    s.flow = f;
    Emitter& e = s.emitters.back();
    e.flow = true;
    e.particles = uint32_t(200 + rng() % 400);
    e.rate = uniform(100.0f, 2000.0f);
    e.mass = detail::defaultFlowMass(f);
    e.velocity = {uniform(-1, 1), uniform(0, 2), uniform(-1, 1)};
    e.spread = {uniform(0.0f, 0.5f), uniform(0.0f, 0.5f), uniform(0.0f, 0.5f)};
    if (rng() % 2) e.temperature = uniform(f.solidus + 10.0f, f.temperature);
  }
  return s;
}

// The rows of a float32 .npy `lava simulate --out` wrote, and their columns.
std::vector<float> npyFloats(const std::string& data, size_t& columns) {
  const size_t shape = data.find("'shape': (");
  const size_t comma = data.find(", ", shape);
  columns = shape == std::string::npos ? 0 : std::stoul(data.substr(comma + 2));
  const size_t header = data.find('\n') + 1;
  std::vector<float> out((data.size() - header) / 4);
  if (!out.empty()) std::memcpy(out.data(), data.data() + header, out.size() * 4);
  return out;
}

// Every check, on the scene in `toml` (a file).
void checkThroughTheProgram(const std::string& toml, const std::string& name) {
  SCOPED_TRACE(name + " (" + toml + ")");
  const Scene s = loadScene(toml);
  const uint64_t half = s.flows() ? 150 : 400;
  const std::string cpu = scratch(name + "-cpu.npy"), gpu = scratch(name + "-gpu.npy"),
                    ck = scratch(name + "-half.npz"), resumed = scratch(name + "-resumed.npy");
  const std::string steps = " --steps " + std::to_string(2 * half);
  cli::Result r = lava("simulate --backend cpu --scene " + toml + steps + " --out " + cpu);
  ASSERT_EQ(r.status, 0) << r.err;
  r = lava("simulate --backend gpu --scene " + toml + steps + " --out " + gpu);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string bytes = readFile(cpu);
  EXPECT_TRUE(bytes == readFile(gpu)) << "the GPU's bytes differ from the CPU's";
  r = lava("simulate --backend gpu --scene " + toml + " --steps " + std::to_string(half) +
           " --checkpoint " + ck);
  ASSERT_EQ(r.status, 0) << r.err;
  r = lava("simulate --resume " + ck + " --steps " + std::to_string(half) + " --out " + resumed);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(bytes == readFile(resumed)) << "the resumed run's bytes differ";

  size_t columns = 0;
  const std::vector<float> v = npyFloats(bytes, columns);
  ASSERT_GE(columns, 7u);
  size_t alive = 0;
  for (size_t row = 0; row * columns < v.size(); ++row) {
    const float* p = &v[row * columns];
    for (size_t c = 0; c < columns; ++c) ASSERT_FALSE(std::isnan(p[c])) << "NaN in row " << row;
    if (p[6] < 0.0f) continue;
    ++alive;
    ASSERT_GE(p[1], 0.0f) << "row " << row << " below the ground";
    for (const Collider& c : s.colliders) {
      const float dx = p[0] - c.position.x, dy = p[1] - c.position.y, dz = p[2] - c.position.z;
      constexpr float eps = 1e-4f;
      bool inside = false;
      switch (c.type) {
        case ColliderType::Plane: {
          const float n = std::sqrt(c.normal.x * c.normal.x + c.normal.y * c.normal.y +
                                    c.normal.z * c.normal.z);
          inside = (dx * c.normal.x + dy * c.normal.y + dz * c.normal.z) / n < -eps;
          break;
        }
        case ColliderType::Sphere:
          inside = std::sqrt(dx * dx + dy * dy + dz * dz) < c.radius - eps;
          break;
        case ColliderType::Box:
          inside = std::fabs(dx) < c.size.x - eps && std::fabs(dy) < c.size.y - eps &&
                   std::fabs(dz) < c.size.z - eps;
          break;
        case ColliderType::Cone: {
          const float ry = c.baseRadius + (c.topRadius - c.baseRadius) * dy / c.height;
          inside = dy > eps && dy < c.height - eps && std::sqrt(dx * dx + dz * dz) < ry - eps;
          break;
        }
      }
      ASSERT_FALSE(inside) << "row " << row << " inside collider " << lava::name(c.type);
    }
  }
  EXPECT_GT(alive, 0u);
}

TEST(Property, KeptScenesStillHold) {
  const std::filesystem::path kept = std::string(LAVA_SOURCE_DIR) + "/tests/property";
  size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kept))
    if (entry.path().extension() == ".toml") {
      checkThroughTheProgram(entry.path().string(), "kept-" + entry.path().stem().string());
      ++n;
    }
  EXPECT_GT(n, 0u);
}

TEST(Property, RandomValidScenesRunExactlyThroughTheProgram) {
  const char* count = std::getenv("LAVA_PROPERTY_SCENES");
  const char* first = std::getenv("LAVA_PROPERTY_SEED");
  const uint32_t scenes = count ? uint32_t(std::strtoul(count, nullptr, 10)) : 4;
  const uint32_t seed0 = first ? uint32_t(std::strtoul(first, nullptr, 10)) : 20261205;
  for (uint32_t k = 0; k < scenes; ++k) {
    const uint32_t seed = seed0 + k;
    const Scene s = propertyScene(seed);
    ASSERT_NO_THROW(lava::checkScene(s)) << "seed " << seed << ": the generator drew an invalid scene";
    const std::string toml = cli::writeScene("property-" + std::to_string(seed) + ".toml", toToml(s));
    checkThroughTheProgram(toml, "seed-" + std::to_string(seed));
    if (HasFailure()) {
      ADD_FAILURE() << "seed " << seed << " failed: keep " << toml << " in tests/property/";
      return;
    }
  }
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

// One to eight edits of `data`: a byte changed, a run deleted, bytes that mean something in
// TOML or numbers inserted, or the end cut off.
std::string mutate(std::string data, std::mt19937& rng) {
  static const char* const kPieces[] = {"0", "9", "-", ".", "e", "e9", "1e38", "=", "[", "]",
                                        "\n", "\"", "#", "particles = ", "flow = true", "nan"};
  const uint32_t edits = 1 + uint32_t(rng() % 8);
  for (uint32_t k = 0; k < edits && !data.empty(); ++k) {
    const size_t at = rng() % data.size();
    switch (rng() % 4) {
      case 0:
        data[at] = char(rng() % 256);
        break;
      case 1:
        data.erase(at, 1 + rng() % 16);
        break;
      case 2:
        data.insert(at, kPieces[rng() % (sizeof(kPieces) / sizeof(kPieces[0]))]);
        break;
      default:
        data.resize(at);
        break;
    }
  }
  return data;
}

TEST(MutatedFiles, ExitZeroOneOrTwoWithOneLineAndNoPartialOutput) {
  // Mutants of the presets, the module scenes and the corpus's checkpoints, through
  // `lava simulate` with --out (and --checkpoint when resuming): exit 0, 1 or 2 within the
  // time limit, never a signal; on failure one line and nothing left in the output folder
  // (no partial file, no temporary); on success exactly the files asked for.
  // LAVA_MUTANTS=N runs N instead of CI's 24.
  const std::string source = LAVA_SOURCE_DIR;
  std::vector<std::string> bases;
  // The corpus's checkpoints written by `lava simulate` (*.npz), not those fuzzing grew.
  for (const char* folder : {"/scenes", "/scenes/modules", "/fuzz/corpus/checkpoint"})
    for (const auto& entry : std::filesystem::directory_iterator(source + folder))
      if (entry.is_regular_file() && (std::string(folder) != "/fuzz/corpus/checkpoint" ||
                                      entry.path().extension() == ".npz"))
        bases.push_back(entry.path().string());
  std::sort(bases.begin(), bases.end());
  const char* count = std::getenv("LAVA_MUTANTS");
  const uint32_t mutants = count ? uint32_t(std::strtoul(count, nullptr, 10)) : 24;
  std::mt19937 rng(424242);
  uint32_t exits[3] = {0, 0, 0};
  for (uint32_t i = 0; i < mutants; ++i) {
    const std::string& base = bases[rng() % bases.size()];
    const bool checkpoint = base.size() > 4 && base.substr(base.size() - 4) == ".npz";
    const std::string file = cli::writeScene(
        "mutant-" + std::to_string(i) + (checkpoint ? ".npz" : ".toml"), mutate(readFile(base), rng));
    const std::string out = scratch("mutant-" + std::to_string(i) + "-out");
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    SCOPED_TRACE(file + " (from " + base + ")");
    const cli::Result r =
        cli::run("timeout 120 " + std::string(LAVA_EXE) + " simulate --steps 20 --out " + out +
                 "/state.npy " +
                 (checkpoint ? "--resume " + file + " --checkpoint " + out + "/next.npz"
                             : "--scene " + file));
    ASSERT_TRUE(r.status == 0 || r.status == 1 || r.status == 2)
        << "exit " << r.status << " (124: the time limit; 128+: a signal)\n" << r.err;
    ++exits[r.status];
    std::vector<std::string> left;
    for (const auto& entry : std::filesystem::directory_iterator(out))
      left.push_back(entry.path().filename().string());
    std::sort(left.begin(), left.end());
    if (r.status == 0) {
      const std::vector<std::string> asked =
          checkpoint ? std::vector<std::string>{"next.npz", "state.npy"}
                     : std::vector<std::string>{"state.npy"};
      EXPECT_EQ(left, asked);
    } else {
      EXPECT_EQ(cli::count(r.err, "\n"), 1) << r.err;
      EXPECT_EQ(r.err.rfind("lava: ", 0), 0u) << r.err;
      EXPECT_TRUE(left.empty()) << left.front();
    }
  }
  std::printf("mutants: %u ran (exit 0), %u failed at run time (1), %u refused (2)\n", exits[0],
              exits[1], exits[2]);
}

}  // namespace
}  // namespace lava
