// What the `lava` program's tests share: running build/lava in a scratch folder of this
// process and reading what it wrote.
#pragma once
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace cli {

struct Result {
  int status;
  std::string out;
  std::string err;
};

inline std::string readFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream s;
  s << file.rdbuf();
  return s.str();
}

// This process's scratch folder, removed when the process that made it exits (a forked child
// sees the same and leaves it). The process exits without gtest's environments too: ctest
// lists the tests with --gtest_list_tests, after the static scenes are written.
class ScratchFolder {
 public:
  ScratchFolder()
      : owner_(getpid()), path_(::testing::TempDir() + "lava_cli_" + std::to_string(owner_) + "/") {
    std::filesystem::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    if (getpid() == owner_) std::filesystem::remove_all(path_, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  pid_t owner_;
  std::string path_;
};

inline const std::string& scratchFolder() {
  static const ScratchFolder folder;
  return folder.path();
}

inline std::string scratch(const std::string& name) { return scratchFolder() + name; }

// Runs a shell command line, capturing its exit status and output.
inline Result run(const std::string& command) {
  const std::string out = scratch("stdout"), err = scratch("stderr");
  const std::string line = command + " >" + out + " 2>" + err + " </dev/null";
  const int raw = std::system(line.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), readFile(out), readFile(err)};
}

// Runs build/lava with `args`; `prefix` goes before it (e.g. an `env` call).
inline Result lava(const std::string& args, const std::string& prefix = "") {
  return run(prefix + std::string(LAVA_EXE) + " " + args);
}

inline std::string writeScene(const std::string& name, const std::string& contents) {
  const std::string path = scratch(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

inline size_t npyRows(const std::string& path) {
  const std::string data = readFile(path);
  const size_t at = data.find("'shape': (");
  return at == std::string::npos ? 0 : std::stoul(data.substr(at + 10));
}

inline int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// A number `lava info` prints after `label` (0 when it is missing).
inline unsigned long long infoNumber(const std::string& info, const std::string& label) {
  const size_t at = info.find(label);
  return at == std::string::npos ? 0 : std::strtoull(info.c_str() + at + label.size(), nullptr, 10);
}

}  // namespace cli
