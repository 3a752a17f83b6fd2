// The command line's own errors and its checks of output paths, before any work starts.
#pragma once
#include <stdexcept>
#include <string>

namespace lava::app {

// Bad input from the user (exit status 2): the message names the flag and what it accepts.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throw UsageError naming `flag` unless `path` ends in `extension` (or, for states, .npy or
// .csv) and its folder is writable.
void checkOutputPath(const std::string& flag, const std::string& path,
                     const std::string& extension);
void checkStatePath(const std::string& flag, const std::string& path);
// Throws UsageError naming `source` unless `path` is a writable folder or one that can be
// created (the command creates it once every other check has passed: a usage error leaves no folder
// behind).
std::string outputFolder(const std::string& source, const std::string& path);
// --series DIR: a folder with a name (DIR.pvd is written beside it) that outputFolder()
// accepts, without its trailing slashes.
std::string seriesFolder(const std::string& flag, const std::string& path);

}  // namespace lava::app
