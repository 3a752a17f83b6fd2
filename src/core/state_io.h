// Writing a particle state as SPEC §4 says: .npy (float32, shape (capacity, 7)) or .csv,
// columns px py pz vx vy vz age, age -1 for never-emitted slots. Files appear whole or not at all.
#pragma once
#include <string>
#include <vector>

#include "shared.h"

namespace lava {

// Throws UsageError naming `flag` unless `path` ends in .npy or .csv and its folder is writable.
void checkStatePath(const std::string& flag, const std::string& path);
// Throws UsageError naming `flag` unless `path` ends in `extension` and its folder is writable.
void checkOutputPath(const std::string& flag, const std::string& path,
                     const std::string& extension);

void writeState(const std::string& path, const std::vector<gpu::Particle>& particles);

// Writes `contents` to `path` through a temporary file renamed into place.
void writeFileAtomically(const std::string& path, const std::string& contents);

// FNV-1a over the particle bytes: a fingerprint for determinism checks.
uint64_t stateHash(const std::vector<gpu::Particle>& particles);

}  // namespace lava
