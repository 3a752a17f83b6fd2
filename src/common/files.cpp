#include "files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "lava/error.h"

namespace lava::common {
namespace {

std::string folderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// The rename itself reaches the disk once the folder is flushed; not every file system
// allows that (the data is already safe then), so its failure is not an error.
void syncFolder(const std::string& path) {
  const int fd = ::open(folderOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  while (fsync(fd) != 0 && errno == EINTR) {
  }
  ::close(fd);
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::string& contents,
                         void (*onTemporary)(const char*)) {
  const auto fail = [&path](int error) {
    throw ResourceError("cannot write '" + path + "': " + std::strerror(error ? error : EIO));
  };
  std::string temporary = path + ".XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) fail(errno);
  if (onTemporary) onTemporary(temporary.c_str());
  const auto discard = [&](int error) {
    std::remove(temporary.c_str());
    if (onTemporary) onTemporary(nullptr);
    fail(error);
  };
  size_t written = 0;
  int error = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    written += size_t(n);
  }
  // mkstemp makes the file 0600; a plain new file gets 0666 less the umask.
  const mode_t mask = umask(0);
  umask(mask);
  if (error == 0 && fchmod(fd, 0666 & ~mask) != 0) error = errno;
  if (error == 0) {
    while (fsync(fd) != 0) {
      if (errno == EINTR) continue;
      error = errno;
      break;
    }
  }
  if (::close(fd) != 0 && error == 0 && errno != EINTR) error = errno;
  if (error != 0) discard(error);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) discard(errno);
  if (onTemporary) onTemporary(nullptr);
  syncFolder(path);
}

bool moveIntoPlace(const std::string& temporary, const std::string& path) {
  const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  bool synced = fd >= 0;
  while (synced && fsync(fd) != 0) synced = errno == EINTR;
  if (fd >= 0) ::close(fd);
  if (!synced || std::rename(temporary.c_str(), path.c_str()) != 0) return false;
  syncFolder(path);
  return true;
}

std::string readWholeFile(const std::string& path, const std::string& what) {
  struct stat info {};
  const std::string name = path.empty() ? what : path;
  if (path.empty() || stat(path.c_str(), &info) != 0)
    throw InvalidArgument(name, "cannot read " + what + ": " +
                                    std::strerror(path.empty() ? ENOENT : errno));
  if (S_ISDIR(info.st_mode)) throw InvalidArgument(path, "is a folder, not " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidArgument(path, "cannot read " + what + ": " + std::strerror(errno));
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace lava::common
