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

}  // namespace lava::app
