// Flags and scene files. The scene flags are the library's scene keys (lava::sceneKeys):
// a scene file, when given, is read first, then the command line overrides it. A command's
// own options can be set from the same file; keys of other commands are passed over.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lava/scene.h"
#include "lava/scene_keys.h"
#include "lava/simulation.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace lava::app {

// Parsers: throw UsageError("<source>: expected ..., got '<text>'").
uint64_t parseInteger(const std::string& source, const std::string& text, uint64_t lo, uint64_t hi);
double parseNumber(const std::string& source, const std::string& text, double lo, double hi,
                   bool loOpen = false);

class Options;

// --backend gpu|cpu|cpu-simd and --threads (docs/cli.md, `lava simulate`).
struct BackendChoice {
  bool gpu = true;
  CpuKernel kernel = CpuKernel::Reference;
  unsigned threads = 0;  // 0: every core
  unsigned cpuThreads() const;
};
void addBackendFlags(Options& options, BackendChoice& backend);

// --series DIR and --every K (docs/cli.md, "Series"), and the check that both or neither
// were given (after resolve()).
void addSeriesFlags(Options& options, std::string& series, uint64_t& every);
void checkSeriesFlags(const std::string& series, uint64_t every);

class Options {
 public:
  using Apply = std::function<void(const std::string& source, const std::string& text)>;

  explicit Options(CLI::App& command);
  // A command option `--name VALUE`, also the scene-file key `name`.
  void add(const std::string& name, const std::string& help, Apply apply, bool required = false);
  // A whole number in [lo, hi] (parseInteger's checks and messages), written into `target`.
  template <typename T>
  void addInteger(const std::string& name, const std::string& help, T& target, uint64_t lo,
                  uint64_t hi, bool required = false) {
    add(
        name, help,
        [&target, lo, hi](const std::string& source, const std::string& text) {
          target = static_cast<T>(parseInteger(source, text, lo, hi));
        },
        required);
  }
  // A boolean `--name`, also `name = true` in a scene file.
  void addFlag(const std::string& name, const std::string& help, bool& value);
  // The scene keys as flags, writing into `scene`, and --device.
  void addSceneFlags(Scene& scene, std::optional<unsigned>& device);
  // After CLI parsing: the scene file, then this command's values from it, then the flags.
  void resolve();
  // Whether --name was given on the command line, and its text.
  bool given(const std::string& name) const;
  const std::string& text(const std::string& name) const { return values_.at(name); }

 private:
  struct Spec {
    std::string name;
    Apply apply;
    bool required;
    CLI::Option* flag;
  };
  static std::set<std::string>& everyKey();  // the options of every command

  CLI::App& command_;
  std::vector<Spec> specs_;
  std::map<std::string, std::string> values_;  // text of each given option
  std::map<std::string, bool*> flags_;
  Scene* scene_ = nullptr;
  std::vector<std::pair<std::string, CLI::Option*>> sceneFlags_;
  std::string scenePath_;
};

}  // namespace lava::app
