#include "output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "lava/error.h"

namespace lava::host {
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

float ageColumn(const Particle& p) {
  return p.age < 0.0f ? -1.0f : p.age;
}

std::string npy(const std::vector<Particle>& particles) {
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
  for (const Particle& p : particles) {
    const float row[7] = {p.px, p.py, p.pz, p.vx, p.vy, p.vz, ageColumn(p)};
    out.append(reinterpret_cast<const char*>(row), sizeof(row));  // x86/ARM: little-endian
  }
  return out;
}

std::string csv(const std::vector<Particle>& particles) {
  std::string out = "px,py,pz,vx,vy,vz,age\n";
  char line[256];
  for (const Particle& p : particles) {
    std::snprintf(line, sizeof(line), "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.px, p.py, p.pz,
                  p.vx, p.vy, p.vz, ageColumn(p));
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

namespace {
// The temporary being written, for removePendingTemporary (a signal handler cannot take locks
// or allocate; it reads a fixed buffer that is published only while complete).
char pendingPath[4096];
volatile std::sig_atomic_t pending = 0;

struct PendingTemporary {
  explicit PendingTemporary(const std::string& path) {
    if (path.size() >= sizeof(pendingPath)) return;
    std::memcpy(pendingPath, path.c_str(), path.size() + 1);
    pending = 1;
  }
  ~PendingTemporary() { pending = 0; }
};
}  // namespace

void removePendingTemporary() {
  if (pending) unlink(pendingPath);
}

void writeFileAtomically(const std::string& path, const std::string& contents) {
  // A temporary of this run's own next to the file, so concurrent writers never share one.
  std::string temporary = path + ".XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) throw ResourceError("cannot write '" + path + "': " + std::strerror(errno));
  const PendingTemporary published(temporary);
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += size_t(n);
  }
  const int saved = errno;
  // Permissions as a plain file would get (mkstemp makes it 0600).
  const mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  if (::close(fd) != 0 || written != contents.size()) {
    std::remove(temporary.c_str());
    throw ResourceError("cannot write '" + path + "': " + std::strerror(saved ? saved : EIO));
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw ResourceError("cannot write '" + path + "': " + reason);
  }
}

void writeState(const std::string& path, const std::vector<Particle>& particles) {
  writeFileAtomically(path, endsWith(path, ".csv") ? csv(particles) : npy(particles));
}

void writePng(const std::string& path, uint32_t width, uint32_t height,
              const std::vector<uint8_t>& rgba) {
  std::string png;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  stbi_write_png_to_func(append, &png, int(width), int(height), 4, rgba.data(), int(width * 4));
  writeFileAtomically(path, png);
}

}  // namespace lava::host
