// Flags and scene files: every option is a named text value parsed and range-checked by one
// function, whether it came from the command line (which wins) or from `--scene FILE`.
#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scene.h"

namespace lava::app {

// Parsers: throw UsageError("<source>: expected ..., got '<text>'").
uint64_t parseInteger(const std::string& source, const std::string& text, uint64_t lo, uint64_t hi);
double parseNumber(const std::string& source, const std::string& text, double lo, double hi,
                   bool loOpen = false);
glm::vec3 parseVec3(const std::string& source, const std::string& text, double lo, double hi);

enum class Kind { Number, Vector, Text };

class Options {
 public:
  using Apply = std::function<void(const std::string& source, const std::string& text)>;

  explicit Options(CLI::App& command);
  // A flag `--name`; also the scene key `name`. Help should give the default and range.
  void add(const std::string& name, Kind kind, const std::string& help, Apply apply,
           bool required = false);
  // The SPEC §2 flags writing into `scene`, plus --device.
  void addSceneFlags(Scene& scene, std::optional<unsigned>& device);
  // After CLI parsing: reads the scene file, then applies each given value in order.
  void resolve();

 private:
  struct Spec {
    std::string name;
    Kind kind;
    Apply apply;
    bool required;
    CLI::Option* flag;
  };
  std::map<std::string, std::string> readScene() const;
  // The flags of every command: a scene file may hold keys of commands other than this one.
  static std::set<std::string>& everyKey();

  CLI::App& command_;
  std::vector<Spec> specs_;
  std::map<std::string, std::string> given_;
  std::string scenePath_;
};

}  // namespace lava::app
