#include "options.h"

#include <CLI/CLI.hpp>
#include <algorithm>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "cli.h"
#include "host/output.h"
#include "lava/error.h"
#include "lava/scene_keys.h"
#include "paths.h"

namespace lava::app {
namespace {

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", value);
  return text;
}

[[noreturn]] void reject(const std::string& source, const std::string& expected,
                         const std::string& text) {
  throw UsageError(source + ": expected " + expected + ", got '" + text + "'");
}

bool readDouble(const std::string& text, double& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return *end == '\0' && errno != ERANGE;
}

}  // namespace

uint64_t parseInteger(const std::string& source, const std::string& text, uint64_t lo,
                      uint64_t hi) {
  const std::string expected =
      "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  double value = 0.0;
  if (!readDouble(text, value) || !std::isfinite(value) || value != std::floor(value))
    reject(source, expected, text);
  if (value < static_cast<double>(lo) || value > static_cast<double>(hi))
    reject(source, expected, text);
  if (text.find_first_not_of("0123456789") == std::string::npos)
    return std::strtoull(text.c_str(), nullptr, 10);  // exact beyond 2^53
  return static_cast<uint64_t>(value);
}

double parseNumber(const std::string& source, const std::string& text, double lo, double hi,
                   bool loOpen) {
  const std::string expected = "a number in " + std::string(loOpen ? "(" : "[") + formatNumber(lo) +
                               ", " + formatNumber(hi) + "]";
  double value = 0.0;
  if (!readDouble(text, value) || !std::isfinite(value)) reject(source, expected, text);
  if (value < lo || value > hi || (loOpen && value == lo)) reject(source, expected, text);
  return value;
}

Options::Options(CLI::App& command) : command_(command) {
  command_.add_option("--scene", scenePath_,
                      "TOML scene file: scene keys, [[emitter]]/[[force]]/[[collider]] tables, "
                      "and this command's options (flags win)");
}

std::set<std::string>& Options::everyKey() {
  static std::set<std::string> keys;
  return keys;
}

void Options::add(const std::string& name, const std::string& help, Apply apply, bool required) {
  everyKey().insert(name);
  CLI::Option* flag = command_.add_option("--" + name, values_[name], help);
  flag->type_name("VALUE");
  specs_.push_back({name, std::move(apply), required, flag});
}

void Options::addFlag(const std::string& name, const std::string& help, bool& value) {
  everyKey().insert(name);
  command_.add_flag("--" + name, value, help);
  flags_[name] = &value;
}

void Options::addSceneFlags(Scene& scene, std::optional<unsigned>& device) {
  scene_ = &scene;
  for (const SceneKey& key : sceneKeys(KeyTable::Top)) {
    CLI::Option* flag = command_.add_option("--" + key.name, values_[key.name],
                                            key.help + " [" + key.fallback + "]");
    flag->type_name(key.kind == KeyKind::Vector ? "X,Y,Z"
                    : key.kind == KeyKind::Name ? "NAME"
                                                : "NUM");
    sceneFlags_.emplace_back(key.name, flag);
  }
  addInteger("device", "Vulkan device index from 'lava info' [best; or LAVA_DEVICE]", device, 0,
             255);
}

bool Options::given(const std::string& name) const {
  if (name == "scene") return command_.count("--scene") > 0;
  for (const Spec& s : specs_)
    if (s.name == name) return s.flag->count() > 0;
  for (const auto& [key, flag] : sceneFlags_)
    if (key == name) return flag->count() > 0;
  return false;
}

void Options::resolve() {
  std::map<std::string, std::string> fromFile;
  if (!scenePath_.empty() || command_.count("--scene") > 0) {
    const auto other = [&](const std::string& key, const std::string& text) {
      const bool ours =
          std::any_of(specs_.begin(), specs_.end(), [&](const Spec& s) { return s.name == key; }) ||
          flags_.count(key);
      if (ours) fromFile[key] = text;
      return ours || everyKey().count(key) > 0;  // another command's option: passed over
    };
    try {
      Scene read = loadScene(scenePath_, other);
      if (scene_) *scene_ = std::move(read);
    } catch (const InvalidArgument& e) {
      if (e.parameter() == scenePath_ || e.parameter() == "scene")  // the file as a whole
        throw UsageError("--scene: " + (scenePath_.empty() ? "" : scenePath_ + ": ") + e.detail());
      throw UsageError(e.what());
    }
  }
  if (scene_)
    for (const auto& [key, flag] : sceneFlags_) {
      if (flag->count() == 0) continue;
      try {
        setSceneKey(*scene_, KeyTable::Top, 0, key, values_.at(key));
      } catch (const InvalidArgument& e) {
        throw UsageError("--" + e.parameter() + ": " + e.detail());
      }
    }
  // What no single key decides (a zero normal, a cone's radii, the emitters' total), named
  // where it came from.
  if (scene_) try {
      checkScene(*scene_);
    } catch (const InvalidArgument& e) {
      throw UsageError((scenePath_.empty() ? "--" : scenePath_ + ": ") + e.what());
    }
  for (const auto& [name, value] : flags_) {
    if (command_.count("--" + name) > 0) continue;
    if (auto it = fromFile.find(name); it != fromFile.end()) {
      if (it->second != "true" && it->second != "false")
        throw UsageError(scenePath_ + ": " + name + ": expected true or false, got '" + it->second +
                         "'");
      *value = it->second == "true";
    }
  }
  for (const Spec& spec : specs_) {
    if (spec.flag->count() > 0) {
      spec.apply("--" + spec.name, values_.at(spec.name));
    } else if (auto it = fromFile.find(spec.name); it != fromFile.end()) {
      spec.apply(scenePath_ + ": " + spec.name, it->second);
    } else if (spec.required) {
      throw UsageError("--" + spec.name + " is required: " + spec.flag->get_description());
    }
  }
  if (parseOnlyMode()) throw ParsedOnly();
}

bool& parseOnlyMode() {
  static bool parseOnly = false;
  return parseOnly;
}

unsigned BackendChoice::cpuThreads() const {
  return threads ? threads : std::max(1u, std::thread::hardware_concurrency());
}

void addBackendFlags(Options& options, BackendChoice& backend) {
  options.add("backend",
              "gpu (the Vulkan device), cpu (the reference) or cpu-simd (its SIMD twin, the "
              "same bytes) [gpu]",
              [&backend](const std::string& src, const std::string& t) {
                if (t != "gpu" && t != "cpu" && t != "cpu-simd")
                  throw UsageError(src + ": expected gpu, cpu or cpu-simd, got '" + t + "'");
                backend.gpu = t == "gpu";
                backend.kernel = t == "cpu-simd" ? CpuKernel::Simd : CpuKernel::Reference;
              });
  options.addInteger("threads", "CPU backend threads, 0 = all cores, 0..1024 [0]", backend.threads,
                     0, 1024);
}

void addSeriesFlags(Options& options, std::string& series, uint64_t& every) {
  options.add(
      "series",
      "also write the state every --every steps as a VTK time series for ParaView: "
      "DIR/step_*.vtp and DIR.pvd beside the folder (created if missing)",
      [&series](const std::string& src, const std::string& t) { series = seriesFolder(src, t); });
  options.addInteger("every", "with --series: the steps between samples, 1..1e9", every, 1,
                     1000000000);
}

void checkSeriesFlags(const std::string& series, uint64_t every) {
  if (!series.empty() && !every)
    throw UsageError("--series: needs --every K, the steps between samples (1..1e9)");
  if (every && series.empty()) throw UsageError("--every: needs --series DIR");
}

}  // namespace lava::app
