// Checkpoint files (a ZIP of .npy arrays): bytes to a scene and state, or InvalidArgument,
// never a crash. What is accepted round-trips: written out again and read back, it is the
// same scene and the same state, bit for bit.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "lava/checkpoint.h"
#include "lava/error.h"
#include "tools/fuzzing.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  lava::compareCheckpointSums(false);  // docs/fuzzing.md
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  lava::Snapshot read;
  try {
    read = lava::parseCheckpoint(bytes, "fuzz.npz");
  } catch (const lava::InvalidArgument&) {
    return 0;
  }
  lava::checkScene(read.scene);
  lava::checkState(read.scene, read.state);
  const lava::Snapshot again =
      lava::parseCheckpoint(lava::checkpointBytes(read.scene, read.state), "written.npz");
  const lava::State& a = read.state;
  const lava::State& b = again.state;
  if (lava::toToml(again.scene) != lava::toToml(read.scene) || a.step != b.step ||
      a.clocks.size() != b.clocks.size() || a.particles.size() != b.particles.size() ||
      std::memcmp(a.particles.data(), b.particles.data(),
                  a.particles.size() * sizeof(lava::Particle)) != 0)
    std::abort();
  for (size_t k = 0; k < a.clocks.size(); ++k)
    if (std::memcmp(&a.clocks[k], &b.clocks[k], sizeof(a.clocks[k])) != 0) std::abort();
  return 0;
}
