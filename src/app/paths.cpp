#include "paths.h"

#include <sys/stat.h>
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

std::string outputFolder(const std::string& source, const std::string& path) {
  if (path.empty()) throw UsageError(source + ": expected a folder, got ''");
  struct stat info {};
  if (stat(path.c_str(), &info) == 0) {
    if (!S_ISDIR(info.st_mode) || access(path.c_str(), W_OK) != 0)
      throw UsageError(source + ": '" + path + "' is not a writable folder");
    return path;
  }
  // Created when the frames are written, not before: a usage error leaves no folder behind.
  const size_t slash = path.find_last_of('/', path.find_last_not_of('/'));
  const std::string parent =
      slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  if (stat(parent.c_str(), &info) != 0 || !S_ISDIR(info.st_mode) ||
      access(parent.c_str(), W_OK) != 0)
    throw UsageError(source + ": cannot create folder '" + path + "': '" + parent +
                           "' is not a writable folder");
  return path;
}

std::string seriesFolder(const std::string& flag, const std::string& path) {
  std::string folder = path;
  while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
  const size_t slash = folder.find_last_of('/');
  const std::string name = slash == std::string::npos ? folder : folder.substr(slash + 1);
  if (name.empty() || name == "." || name == "..")
    throw UsageError(flag + ": expected a folder with a name, such as out/run (run.pvd is " +
                     "written beside it), got '" + path + "'");
  outputFolder(flag, folder);
  const std::string pvd = folder + ".pvd", parent = folderOf(pvd);
  struct stat info {};
  if (stat(pvd.c_str(), &info) == 0 && S_ISDIR(info.st_mode))
    throw UsageError(flag + ": cannot write '" + pvd + "': it is a folder");
  if (access(parent.c_str(), W_OK) != 0)
    throw UsageError(flag + ": cannot write '" + pvd + "': folder '" + parent +
                     "' is not writable");
  return folder;
}

}  // namespace lava::app
