#include "state_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "vk_check.h"

namespace lava {
namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string folderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

float ageColumn(const gpu::Particle& p) {
  return p.posAge.w < 0.0f ? -1.0f : p.posAge.w;
}

std::string npy(const std::vector<gpu::Particle>& particles) {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(particles.size()) + ", 7), }";
  const size_t preamble = 10;  // magic (6) + version (2) + header length (2)
  header.append(63 - (preamble + header.size()) % 64, ' ');
  header.push_back('\n');
  std::string out("\x93NUMPY\x01\x00", 8);
  out.push_back(static_cast<char>(header.size() & 0xff));
  out.push_back(static_cast<char>(header.size() >> 8));
  out += header;
  out.reserve(out.size() + particles.size() * 7 * sizeof(float));
  for (const gpu::Particle& p : particles) {
    const float row[7] = {p.posAge.x,  p.posAge.y,  p.posAge.z,  p.velMass.x,
                          p.velMass.y, p.velMass.z, ageColumn(p)};
    out.append(reinterpret_cast<const char*>(row), sizeof(row));  // x86/ARM: little-endian
  }
  return out;
}

std::string csv(const std::vector<gpu::Particle>& particles) {
  std::string out = "px,py,pz,vx,vy,vz,age\n";
  char line[256];
  for (const gpu::Particle& p : particles) {
    std::snprintf(line, sizeof(line), "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.posAge.x,
                  p.posAge.y, p.posAge.z, p.velMass.x, p.velMass.y, p.velMass.z, ageColumn(p));
    out += line;
  }
  return out;
}

}  // namespace

void checkOutputPath(const std::string& flag, const std::string& path,
                     const std::string& extension) {
  if (!endsWith(path, extension))
    throw UsageError(flag + ": expected a file name ending in " + extension + ", got '" + path +
                     "'");
  const std::string folder = folderOf(path);
  if (access(folder.c_str(), W_OK) != 0)
    throw UsageError(flag + ": cannot write '" + path + "': folder '" + folder + "' " +
                     (errno == ENOENT ? "does not exist" : "is not writable"));
}

void checkStatePath(const std::string& flag, const std::string& path) {
  if (!endsWith(path, ".npy") && !endsWith(path, ".csv"))
    throw UsageError(flag + ": expected a file name ending in .npy or .csv, got '" + path + "'");
  checkOutputPath(flag, path, path.substr(path.size() - 4));
}

void writeFileAtomically(const std::string& path, const std::string& contents) {
  const std::string temporary = path + ".partial";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    file.close();
    if (!file) {
      std::remove(temporary.c_str());
      throw ResourceError("cannot write '" + path + "': " + std::strerror(errno));
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw ResourceError("cannot write '" + path + "': " + reason);
  }
}

void writeState(const std::string& path, const std::vector<gpu::Particle>& particles) {
  writeFileAtomically(path, endsWith(path, ".csv") ? csv(particles) : npy(particles));
}

uint64_t stateHash(const std::vector<gpu::Particle>& particles) {
  uint64_t hash = 1469598103934665603ull;
  const auto* bytes = reinterpret_cast<const unsigned char*>(particles.data());
  for (size_t i = 0; i < particles.size() * sizeof(gpu::Particle); ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace lava
