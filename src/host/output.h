// The program's files: particle states as .npy or .csv, PNG frames, any text; each appears
// whole (through a temporary of its own in the same folder, renamed into place) or not at all.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lava/state.h"

namespace lava::host {

// .npy (float32, shape (slots, 7)) or .csv, columns px py pz vx vy vz age (-1: not alive),
// and an 8th, temperature (K), for a state with a flow (common/npy.h).
void writeState(const std::string& path, const State& state);
void writePng(const std::string& path, uint32_t width, uint32_t height,
              const std::vector<uint8_t>& rgba);
void writeFileAtomically(const std::string& path, const std::string& contents);

// From a signal handler (async-signal-safe): remove the temporary being written, if any, so
// an interrupted write leaves nothing behind.
void removePendingTemporary();

}  // namespace lava::host
