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

#include "common/files.h"
#include "common/npy.h"
#include "lava/error.h"

namespace lava::host {
namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string npy(const State& state) {
  return common::npyHeader("'<f4'", "(" + std::to_string(state.particles.size()) + ", " +
                                        std::to_string(common::stateColumns(state)) + ")") +
         common::stateTable(state);
}

std::string csv(const State& state) {
  const size_t columns = common::stateColumns(state);
  std::string out = columns == 8 ? "px,py,pz,vx,vy,vz,age,temperature\n" : "px,py,pz,vx,vy,vz,age\n";
  char line[32];
  for (size_t i = 0; i < state.particles.size(); ++i) {
    float row[8];
    common::stateRow(state, i, row);
    for (size_t c = 0; c < columns; ++c) {
      std::snprintf(line, sizeof(line), "%.9g%c", double(row[c]), c + 1 < columns ? ',' : '\n');
      out += line;
    }
  }
  return out;
}

}  // namespace

namespace {
// The temporary being written, for removePendingTemporary (a signal handler cannot take locks
// or allocate; it reads a fixed buffer that is published only while complete).
char pendingPath[4096];
volatile std::sig_atomic_t pending = 0;

void publishTemporary(const char* temporary) {
  pending = 0;
  if (temporary == nullptr || std::strlen(temporary) >= sizeof(pendingPath)) return;
  std::memcpy(pendingPath, temporary, std::strlen(temporary) + 1);
  pending = 1;
}
}  // namespace

void removePendingTemporary() {
  if (pending) unlink(pendingPath);
}

void writeFileAtomically(const std::string& path, const std::string& contents) {
  common::writeFileAtomically(path, contents, publishTemporary);
}

void writeState(const std::string& path, const State& state) {
  writeFileAtomically(path, endsWith(path, ".csv") ? csv(state) : npy(state));
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
