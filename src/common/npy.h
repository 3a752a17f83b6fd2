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

// The state table: float32 (slots, 7), columns px py pz vx vy vz age, -1 for a slot not
// alive; little-endian, as x86 and Arm store floats.
inline std::string stateTable(const std::vector<Particle>& particles) {
  std::string out;
  out.reserve(particles.size() * 7 * sizeof(float));
  for (const Particle& p : particles) {
    const float row[7] = {p.px, p.py, p.pz, p.vx, p.vy, p.vz, p.age < 0.0f ? -1.0f : p.age};
    out.append(reinterpret_cast<const char*>(row), sizeof(row));
  }
  return out;
}

}  // namespace lava::common
