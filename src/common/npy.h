// NumPy's .npy format, version 1.0: the program's state files and the checkpoint's members.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lava/state.h"

namespace lava::common {

// The magic, version and header of an array of dtype `descr` ("'<f4'") and shape `shape`
// ("(5000, 7)"), padded so that the data starts on a multiple of 64 bytes.
inline std::string npyHeader(const std::string& descr, const std::string& shape) {
  std::string header = "{'descr': " + descr + ", 'fortran_order': False, 'shape': " + shape + ", }";
  const size_t preamble = 10;  // magic (6) + version (2) + header length (2)
  header.append(63 - (preamble + header.size()) % 64, ' ');
  header.push_back('\n');
  std::string out("\x93NUMPY\x01\x00", 8);
  out.push_back(static_cast<char>(header.size() & 0xff));
  out.push_back(static_cast<char>(header.size() >> 8));
  return out + header;
}

// The state table's columns: px py pz vx vy vz age (-1 for a slot not alive), then, for a
// state with a flow, temperature (K; 0 for the other emitters' slots and slots not alive).
inline size_t stateColumns(const State& state) {
  return state.temperature.empty() ? 7 : 8;
}
inline void stateRow(const State& state, size_t slot, float row[8]) {
  const Particle& p = state.particles[slot];
  const bool alive = !(p.age < 0.0f);
  row[0] = p.px, row[1] = p.py, row[2] = p.pz, row[3] = p.vx, row[4] = p.vy, row[5] = p.vz;
  row[6] = alive ? p.age : -1.0f;
  row[7] = state.temperature.empty() || !alive ? 0.0f : state.temperature[slot];
}

// The state table as float32 (slots, stateColumns()), little-endian, as x86 and Arm store
// floats.
inline std::string stateTable(const State& state) {
  const size_t columns = stateColumns(state);
  std::string out;
  out.reserve(state.particles.size() * columns * sizeof(float));
  for (size_t i = 0; i < state.particles.size(); ++i) {
    float row[8];
    stateRow(state, i, row);
    out.append(reinterpret_cast<const char*>(row), columns * sizeof(float));
  }
  return out;
}

}  // namespace lava::common
