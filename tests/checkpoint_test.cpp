// The checkpoint file: what is written is read back exactly; a damaged file, of
// any length or with any byte changed, is refused by name, never read as a state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "lava/lava.h"
#include "lava/checkpoint.h"

namespace lava {
namespace {

Scene twoEmitters() {
  Scene s = parseScene(R"(
format = 2
integrator = "velocity-verlet"
[[emitter]]
particles = 300
rate = 2000
[[emitter]]
particles = 200
shape = "box"
lifetime = 0.4
[[collider]]
type = "cone"
)",
                       "scene");
  return s;
}

State someState(const Scene& s) {
  CpuSimulation sim(s, 1);
  sim.advance(700);
  return sim.state();
}

std::string message(const std::string& bytes) {
  try {
    parseCheckpoint(bytes, "ck.npz");
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "ck.npz");
    return e.detail();
  }
  return "(accepted)";
}

TEST(Checkpoint, ReadsBackExactlyWhatWasWritten) {
  const Scene s = twoEmitters();
  const State state = someState(s);
  const Snapshot back = parseCheckpoint(checkpointBytes(s, state), "ck.npz");
  EXPECT_EQ(toToml(back.scene), toToml(s));
  EXPECT_EQ(back.state.step, 700u);
  ASSERT_EQ(back.state.particles.size(), state.particles.size());
  EXPECT_EQ(std::memcmp(back.state.particles.data(), state.particles.data(),
                        state.particles.size() * sizeof(Particle)),
            0);
  ASSERT_EQ(back.state.clocks.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back.state.clocks[k].accumulator, state.clocks[k].accumulator);
    EXPECT_EQ(back.state.clocks[k].serial, state.clocks[k].serial);
    EXPECT_EQ(back.state.clocks[k].head, state.clocks[k].head);
  }
  // And it continues as the original run does.
  CpuSimulation a(s, 1), b(back.scene, 1);
  a.setState(state);
  b.setState(back.state);
  a.advance(100);
  b.advance(100);
  EXPECT_EQ(stateHash(a.state().particles), stateHash(b.state().particles));
}

TEST(Checkpoint, EveryTruncationIsRefused) {
  const Scene s = twoEmitters();
  const std::string bytes = checkpointBytes(s, someState(s));
  for (size_t n = 0; n < bytes.size(); n += n < 256 ? 1 : 97) {
    const std::string what = message(bytes.substr(0, n));
    EXPECT_NE(what, "(accepted)") << "truncated to " << n << " bytes";
  }
  EXPECT_NE(message(bytes.substr(0, bytes.size() - 1)), "(accepted)");
}

TEST(Checkpoint, EveryChangedByteIsRefusedOrHarmless) {
  // A flipped bit anywhere: refused (CRC, checksum, structure), or in a byte no reader uses
  // (a ZIP field Lava does not read); never a different state.
  const Scene s = twoEmitters();
  const State state = someState(s);
  const std::string bytes = checkpointBytes(s, state);
  size_t refused = 0;
  for (size_t at = 0; at < bytes.size(); at += 13) {
    std::string changed = bytes;
    changed[at] = char(changed[at] ^ 0x10);
    try {
      const Snapshot back = parseCheckpoint(changed, "ck.npz");
      EXPECT_EQ(stateHash(back.state.particles), stateHash(state.particles)) << "byte " << at;
      EXPECT_EQ(toToml(back.scene), toToml(s)) << "byte " << at;
    } catch (const InvalidArgument&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, bytes.size() / 13 * 9 / 10);
}

TEST(Checkpoint, NamesWhatIsWrong) {
  const Scene s = twoEmitters();
  const std::string bytes = checkpointBytes(s, someState(s));
  EXPECT_NE(message("hello").find("not a checkpoint"), std::string::npos);
  EXPECT_NE(message(std::string(4096, 'x')).find("not a ZIP"), std::string::npos);
  EXPECT_NE(message(bytes.substr(0, bytes.size() / 2)).find("truncated"), std::string::npos);
  // A different format version, with valid CRCs: rebuild the archive around it.
  std::string other = bytes;
  const size_t format = other.find("\x93NUMPY");
  ASSERT_NE(format, std::string::npos);
  const size_t data = format + 10 + size_t(uint8_t(other[format + 8]));
  other[data] = 9;  // format 9: the CRC no longer matches either
  EXPECT_NE(message(other).find("CRC mismatch in format.npy"), std::string::npos) << message(other);
}

TEST(Checkpoint, RefusesAStateThatDoesNotFitItsScene) {
  const Scene s = twoEmitters();
  State state = someState(s);
  state.particles.pop_back();
  EXPECT_THROW(checkpointBytes(s, state), InvalidArgument);
}

}  // namespace
}  // namespace lava

namespace lava {
namespace {

TEST(Checkpoint, AFlowsTemperaturesAndCrustAreReadBackAndChecked) {
  Scene s = parseScene(R"(
[[emitter]]
particles = 40
rate = 0
burst = 40
shape = "box"
size = [0.05, 0.05, 0.05]
position = [0, 0.06, 0]
velocity = [0, 0, 0]
spread = [0, 0, 0]
flow = true
[flow]
cooling-air = 20
)",
                       "flow");
  CpuSimulation sim(s, 1);
  sim.advance(200);
  const State state = sim.state();
  ASSERT_GT(std::count(state.crust.begin(), state.crust.end(), 1), 0) << "some crust to keep";
  const std::string bytes = checkpointBytes(s, state);
  const Snapshot back = parseCheckpoint(bytes, "ck.npz");
  EXPECT_EQ(back.state.temperature, state.temperature);
  EXPECT_EQ(back.state.crust, state.crust);
  size_t refused = 0, tries = 0;
  for (size_t at = 0; at < bytes.size(); at += 7, ++tries) {
    std::string changed = bytes;
    changed[at] = char(changed[at] ^ 0x04);
    try {
      const Snapshot other = parseCheckpoint(changed, "ck.npz");
      EXPECT_EQ(other.state.temperature, state.temperature) << "byte " << at;
      EXPECT_EQ(other.state.crust, state.crust) << "byte " << at;
      EXPECT_EQ(stateHash(other.state.particles), stateHash(state.particles)) << "byte " << at;
    } catch (const InvalidArgument&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, tries * 3 / 4);  // the rest: ZIP fields and header padding no reader uses
  // The scene without its flow does not take these arrays, nor the flow's scene a state
  // without them.
  Scene plain = s;
  plain.flow.reset();
  plain.emitters[0].flow = false;
  State bare = state;
  bare.temperature.clear();
  bare.crust.clear();
  EXPECT_THROW(checkpointBytes(plain, state), InvalidArgument);
  EXPECT_THROW(checkpointBytes(s, bare), InvalidArgument);
}

}  // namespace
}  // namespace lava
