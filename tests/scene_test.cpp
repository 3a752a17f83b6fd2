// The scene as data: keys set from text with ranges and names in their errors, checkScene()
// naming the offending table entry, format-2 TOML in and out (round trip exact).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "lava/error.h"
#include "lava/scene.h"
#include "lava/scene_keys.h"

namespace lava {
namespace {

std::string parameterOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidArgument& e) {
    return e.parameter();
  }
  return "(nothing thrown)";
}

TEST(SceneKeys, TextSetsTheFieldsAndBadValuesNameTheKey) {
  Scene s;
  setSceneKey(s, KeyTable::Top, 0, "rate", "2500");
  setSceneKey(s, KeyTable::Top, 0, "emitter", "1, 2.5 ,-3");  // spaces around components
  setSceneKey(s, KeyTable::Top, 0, "integrator", "velocity-verlet");
  setSceneKey(s, KeyTable::Top, 0, "shape", "box");
  EXPECT_EQ(s.emitters[0].rate, 2500.0);
  EXPECT_EQ(s.emitters[0].position, (Vec3{1.0f, 2.5f, -3.0f}));
  EXPECT_EQ(s.integrator, Integrator::VelocityVerlet);
  EXPECT_EQ(s.emitters[0].shape, Shape::Box);
  EXPECT_EQ(parameterOf([&] { setSceneKey(s, KeyTable::Top, 0, "restitution", "1.5"); }),
            "restitution");
  EXPECT_EQ(parameterOf([&] { setSceneKey(s, KeyTable::Top, 0, "gravity", "1e-7"); }), "gravity")
      << "non-zero magnitudes below 2^-20 are refused";
  EXPECT_EQ(parameterOf([&] { setSceneKey(s, KeyTable::Top, 0, "shape", "torus"); }), "shape");
  EXPECT_EQ(parameterOf([&] { setSceneKey(s, KeyTable::Top, 0, "wind", "1,2"); }), "wind");
  EXPECT_EQ(parameterOf([&] { setSceneKey(s, KeyTable::Top, 0, "lava-temperature", "3"); }),
            "lava-temperature");
}

TEST(SceneKeys, ValidateNamesTheTableEntry) {
  Scene s;
  s.emitters.resize(3);
  s.emitters[1].radius = -1.0f;
  EXPECT_EQ(parameterOf([&] { checkScene(s); }), "emitter[1].radius");
  s.emitters[1].radius = 0.5f;
  s.colliders.resize(2);
  s.colliders[1].normal = {0.0f, 0.0f, 0.0f};
  EXPECT_EQ(parameterOf([&] { checkScene(s); }), "collider[1].normal");
  s.colliders[1].normal = {0.0f, 1.0f, 0.0f};
  s.emitters.resize(17);
  EXPECT_EQ(parameterOf([&] { checkScene(s); }), "emitter");
  s.emitters.resize(2);
  s.emitters[0].particles = 0x80000000u;
  EXPECT_EQ(parameterOf([&] { checkScene(s); }), "particles");
}

TEST(SceneToml, FormatTwoTablesAndFlatKeys) {
  const Scene s = parseScene(R"(
format = 2
dt = 0.002
integrator = "semi-implicit-euler"
[[emitter]]
particles = 100
shape = "sphere"
radius = 0.25
[[emitter]]
particles = 50
rate = 10
size = [0.1, 0.2, 0.3]
shape = "box"
[[force]]
type = "vortex"
axis = [0, 2, 0]
[[collider]]
type = "cone"
base-radius = 2
top-radius = 0.5
height = 1
)",
                             "inline");
  ASSERT_EQ(s.emitters.size(), 2u);
  EXPECT_EQ(s.particles(), 150u);
  EXPECT_EQ(s.firstSlot(1), 100u);
  EXPECT_EQ(s.emitters[0].shape, Shape::Sphere);
  EXPECT_EQ(s.emitters[1].size, (Vec3{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(s.forces.at(0).type, ForceType::Vortex);
  EXPECT_EQ(s.colliders.at(0).type, ColliderType::Cone);
  EXPECT_EQ(s.colliders[0].height, 1.0f);
  EXPECT_EQ(s.dt, 0.002);
  EXPECT_EQ(s.integrator, Integrator::SemiImplicitEuler);
  const Scene flat = parseScene("particles = 7\nemitter = [0, 2, 0]\nrate = 3\n", "flat");
  EXPECT_EQ(flat.emitters.size(), 1u);
  EXPECT_EQ(flat.emitters[0].particles, 7u);
  EXPECT_EQ(flat.emitters[0].position.y, 2.0f);
}

TEST(SceneToml, BadDataNamesTheKeyAndTableIndex) {
  const std::pair<const char*, const char*> cases[] = {
      {"[[collider]]\ntype = \"torus\"\n", "f: collider[0].type"},
      {"[[emitter]]\n[[emitter]]\nradius = -2\n", "f: emitter[1].radius"},
      {"[[emitter]]\nposition = [1, 2]\n", "f: emitter[0].position"},
      {"[[emitter]]\nsize = [1, -2, 1]\n", "f: emitter[0].size (component y)"},
      {"[[emitter]]\nlava = 1\n", "f: emitter[0].lava"},
      {"[[force]]\nstrength = \"big\"\n", "f: force[0].strength"},
      {"rate = 5\n[[emitter]]\nparticles = 10\n", "f: rate"},  // a flat key beside tables
      {"format = 3\n", "f: format"},
      {"[emitter]\nx = 1\n", "f: emitter"},
  };
  for (const auto& c : cases)  // no structured binding: a lambda cannot capture one in C++17
    EXPECT_EQ(parameterOf([&] { parseScene(c.first, "f"); }), c.second) << c.first;
  std::string many;
  for (int i = 0; i < 17; ++i) many += "[[emitter]]\n";
  EXPECT_EQ(parameterOf([&] { parseScene(many, "f"); }), "f: emitter");
  EXPECT_EQ(parameterOf([&] { checkScene(parseScene("[[collider]]\nnormal = [0, 0, 0]\n", "f")); }),
            "collider[0].normal");
}

// fuzz/regressions/scene/: a letter outside ASCII where toml++ 3.3 tests for whitespace
// reached __builtin_unreachable() (UndefinedBehaviorSanitizer). toml++ now sees only ASCII;
// such a character is refused where it means something, naming the line, and welcome in
// comments.
TEST(SceneToml, ACharacterOutsideAsciiIsRefusedOutsideComments) {
  const std::string cyrillic = "\xd0\x9d";  // U+041D
  for (const std::string& text :
       {"dt = 0.001\nvelocity = [0, 3.2, " + cyrillic + "\n", "gravity = 9.8" + cyrillic + "\n",
        "# ok " + cyrillic + "\n\n\n[[emitter]]\n" + cyrillic + "rate = 5\n",
        "x = '" + cyrillic, "x = \"\"\"a\\\n  " + cyrillic + "\"\"\"\n",
        "integrator = \"" + cyrillic + "\"\n", "seed = 8888E\"x" + cyrillic + "\"\n"}) {
    try {
      parseScene(text, "fuzzed.toml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InvalidArgument& e) {
      EXPECT_FALSE(e.parameter().empty());
    }
  }
  try {  // the line named: the fifth
    parseScene("# ok " + cyrillic + "\n\n\n[[emitter]]\n" + cyrillic + "rate = 5\n", "f.toml");
    ADD_FAILURE() << "accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "f.toml");
    EXPECT_EQ(std::string(e.detail()).rfind("5:1: a character outside ASCII", 0), 0u)
        << e.detail();
  }
  const Scene scene = parseScene("# Größe \xe2\x80\x94 " + cyrillic + "\ndt = 0.002  # " +
                                     cyrillic + "\nintegrator = 'velocity-verlet'\n",
                                 "fine.toml");
  EXPECT_EQ(scene.dt, 0.002);
}

// fuzz/regressions/scene/negative-zero-round-trip.toml: -0.0 was written "-0", which TOML
// reads as the integer 0.
TEST(SceneToml, NegativeZeroReadsBackNegative) {
  const Scene scene = parseScene("[[collider]]\ntype = \"box\"\nposition = [-0.0, 1, 0]\n", "z");
  const std::string written = toToml(scene);
  EXPECT_NE(written.find("position = [-0.0,1,0]"), std::string::npos) << written;
  EXPECT_TRUE(std::signbit(parseScene(written, "again").colliders[0].position.x));
}

TEST(SceneToml, ToTomlReadsBackExactly) {
  Scene s;
  s.dt = 0.0013;
  s.gravity = 9.80665f;
  s.seed = 4000000000u;
  s.integrator = Integrator::VelocityVerlet;
  s.emitters[0].rate = 1234.5678;
  s.emitters[0].velocity = {0.1f, 1.0f / 3.0f, -2.0f};
  s.emitters.push_back(s.emitters[0]);
  s.emitters[1].shape = Shape::Point;
  s.emitters[1].lifetime = 0.7f;
  s.emitters[1].burst = 9;
  s.emitters[1].burstInterval = 0.125;
  s.forces.push_back({ForceType::Attractor, {1, 2, 3}, {0, 1, 0}, 4.5f, 0.75f});
  Collider c;
  c.type = ColliderType::Plane;
  c.normal = {0.0f, 0.6f, 0.8f};
  s.colliders.push_back(c);
  const std::string text = toToml(s);
  const Scene back = parseScene(text, "round trip");
  EXPECT_EQ(toToml(back), text);
  EXPECT_EQ(back.dt, s.dt);
  EXPECT_EQ(back.seed, s.seed);
  EXPECT_EQ(back.emitters[0].rate, s.emitters[0].rate);
  EXPECT_EQ(back.emitters[0].velocity.y, s.emitters[0].velocity.y);
  EXPECT_EQ(back.emitters[1].lifetime, 0.7f);
  EXPECT_EQ(back.forces[0].radius, 0.75f);
  EXPECT_EQ(back.colliders[0].normal, c.normal);
}

}  // namespace
}  // namespace lava
