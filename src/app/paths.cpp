#include "paths.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace lava::app {
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

}  // namespace lava::app
