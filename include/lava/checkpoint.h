// In liblava_tools (Lava::lava_tools, pkg-config lava_tools), beside liblava.
// Checkpoints: a run's scene and state in one file, so that it resumes bit for bit, on the
// same backend or the other, here or on another machine.
//
// The file is a NumPy .npz (a ZIP archive of .npy arrays, stored uncompressed, ZIP64), so
// numpy reads it without Lava:
//
//   z = numpy.load("run.npz")
//   z["state"]      float32 (slots, 7): px py pz vx vy vz age, as `lava simulate --out`
//   z["particles"]  float32 (slots, 8): the raw particles, px py pz age vx vy vz mass
//   z["clock"]      (emitters,) records: accumulator <f8, serial <u8, head <u4
//   z["step"]       uint64 (): steps taken since the run began
//   z["scene"]      uint8: the scene as format-2 TOML text (bytes(z["scene"]).decode())
//   z["format"]     uint32 (1,): kCheckpointFormat
//   z["hash"]       uint64 (1,): stateHash() of the particles
//   z["checksum"]   uint64 (1,): FNV-1a of format, scene, step, clock and particles' bytes
//
// Every member also carries the ZIP's CRC-32; a reader checks both.
#pragma once
#include <cstdint>
#include <string>

#include "export.h"
#include "scene.h"
#include "state.h"

namespace lava {

constexpr uint32_t kCheckpointFormat = 1;

struct Snapshot {
  Scene scene;
  State state;
};

// The checkpoint's bytes (checkState(scene, state) first).
LAVA_TOOLS_API std::string checkpointBytes(const Scene& scene, const State& state);
// Writes them to `path` atomically: a temporary file in the same folder, renamed into place
// (an earlier file at `path` stays whole until then). Throws ResourceError when it cannot.
LAVA_TOOLS_API void writeCheckpoint(const std::string& path, const Scene& scene, const State& state);

// Reads a checkpoint. Throws InvalidArgument whose parameter is `name` (or the path) and
// whose text names the problem: not a checkpoint, truncated, another format version, a
// CRC or checksum mismatch, a scene or state that does not fit.
LAVA_TOOLS_API Snapshot parseCheckpoint(const std::string& bytes, const std::string& name);
LAVA_TOOLS_API Snapshot readCheckpoint(const std::string& path);

}  // namespace lava
