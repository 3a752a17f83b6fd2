#include "options.h"

#include <toml++/toml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "vk_check.h"

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

std::string tomlText(const std::string& source, const toml::node& node, Kind kind) {
  auto number = [&](const toml::node& n) -> std::string {
    if (auto i = n.as_integer()) return std::to_string(i->get());
    if (auto f = n.as_floating_point()) {
      char text[40];
      std::snprintf(text, sizeof(text), "%.17g", f->get());
      return text;
    }
    std::ostringstream type;
    type << n.type();
    throw UsageError(source + ": expected a number, got a TOML " + type.str());
  };
  switch (kind) {
    case Kind::Number:
      return number(node);
    case Kind::Vector: {
      const toml::array* array = node.as_array();
      if (!array) throw UsageError(source + ": expected an array of 3 numbers like [0, 1.5, 0]");
      std::string joined;
      for (const toml::node& element : *array)
        joined += (joined.empty() ? "" : ",") + number(element);
      return joined;
    }
    case Kind::Text:
      if (auto text = node.as_string()) return text->get();
      throw UsageError(source + ": expected a string");
  }
  return {};
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

glm::vec3 parseVec3(const std::string& source, const std::string& text, double lo, double hi) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');) parts.push_back(part);
  if (parts.size() != 3 || text.back() == ',')
    reject(source,
           "3 comma-separated numbers X,Y,Z each in [" + formatNumber(lo) + ", " +
               formatNumber(hi) + "]",
           text);
  glm::vec3 v;
  for (int i = 0; i < 3; ++i)
    v[i] =
        static_cast<float>(parseNumber(source + " (component " + "xyz"[i] + ")", parts[i], lo, hi));
  return v;
}

Options::Options(CLI::App& command) : command_(command) {
  command_.add_option("--scene", scenePath_,
                      "TOML scene file; keys are flag names without '--' (flags win)");
}

std::set<std::string>& Options::everyKey() {
  static std::set<std::string> keys;
  return keys;
}

void Options::add(const std::string& name, Kind kind, const std::string& help, Apply apply,
                  bool required) {
  everyKey().insert(name);
  auto* flag = command_.add_option("--" + name, given_[name], help);
  if (kind == Kind::Vector)
    flag->type_name("X,Y,Z");
  else if (kind == Kind::Number)
    flag->type_name("NUM");
  else
    flag->type_name("TEXT");
  specs_.push_back({name, kind, std::move(apply), required, flag});
}

std::map<std::string, std::string> Options::readScene() const {
  std::map<std::string, std::string> values;
  if (scenePath_.empty()) return values;
  std::ifstream file(scenePath_, std::ios::binary);
  if (!file) throw UsageError("--scene: cannot read '" + scenePath_ + "'");
  std::stringstream contents;
  contents << file.rdbuf();
  toml::table table;
  try {
    table = toml::parse(contents.str(), scenePath_);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw UsageError("--scene: " + scenePath_ + ":" + std::to_string(where.line) + ":" +
                     std::to_string(where.column) + ": not valid TOML (" +
                     std::string(e.description()) + ")");
  }
  for (const auto& [key, node] : table) {
    const std::string name(key.str());
    const std::string source = scenePath_ + ": " + name;
    auto spec =
        std::find_if(specs_.begin(), specs_.end(), [&](const Spec& s) { return s.name == name; });
    if (spec == specs_.end()) {
      if (everyKey().count(name)) continue;  // another command's flag: one scene serves all
      std::string known;
      for (const Spec& s : specs_) known += (known.empty() ? "" : ", ") + s.name;
      throw UsageError(source + ": unknown key (accepted: " + known + ")");
    }
    values[name] = tomlText(source, node, spec->kind);
  }
  return values;
}

void Options::resolve() {
  const std::map<std::string, std::string> scene = readScene();
  for (const Spec& spec : specs_) {
    if (spec.flag->count() > 0) {
      spec.apply("--" + spec.name, given_.at(spec.name));
    } else if (auto it = scene.find(spec.name); it != scene.end()) {
      spec.apply(scenePath_ + ": " + spec.name, it->second);
    } else if (spec.required) {
      throw UsageError("--" + spec.name + " is required: " + spec.flag->get_description());
    }
  }
}

void Options::addSceneFlags(Scene& s, std::optional<unsigned>& device) {
  const Scene d;
  auto vec = [](const glm::vec3& v) {
    return formatNumber(v.x) + "," + formatNumber(v.y) + "," + formatNumber(v.z);
  };
  auto f = [](float v) { return formatNumber(v); };
  add("particles", Kind::Number,
      "ring-buffer capacity, 1..2^31 (device permitting) [" + std::to_string(d.particles) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.particles = static_cast<uint32_t>(parseInteger(src, t, 1, 0x80000000u));
      });
  add("rate", Kind::Number, "emission rate in particles/s, 0..1e9 [" + formatNumber(d.rate) + "]",
      [&s](const std::string& src, const std::string& t) { s.rate = parseNumber(src, t, 0, 1e9); });
  add("dt", Kind::Number, "step h in seconds, 1e-6..1 [" + f(d.dt) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.dt = static_cast<float>(parseNumber(src, t, 1e-6, 1));
      });
  add("gravity", Kind::Number, "g in m/s^2, -1000..1000 [" + f(d.gravity) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.gravity = static_cast<float>(parseNumber(src, t, -1000, 1000));
      });
  add("restitution", Kind::Number, "bounce coefficient epsilon, 0..1 [" + f(d.restitution) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.restitution = static_cast<float>(parseNumber(src, t, 0, 1));
      });
  add("friction", Kind::Number,
      "tangential velocity kept per bounce alpha, 0..1 [" + f(d.friction) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.friction = static_cast<float>(parseNumber(src, t, 0, 1));
      });
  add("line-scale", Kind::Number, "line length s in seconds, 0..10 [" + f(d.lineScale) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.lineScale = static_cast<float>(parseNumber(src, t, 0, 10));
      });
  add("emitter", Kind::Vector, "emitter centre in m, each -1e4..1e4 [" + vec(d.emitter) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.emitter = parseVec3(src, t, -1e4, 1e4);
      });
  add("emitter-radius", Kind::Number,
      "emitter disc radius in m, 0..1e4 [" + f(d.emitterRadius) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.emitterRadius = static_cast<float>(parseNumber(src, t, 0, 1e4));
      });
  add("velocity", Kind::Vector,
      "mean launch velocity in m/s, each -1e4..1e4 [" + vec(d.velocity) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.velocity = parseVec3(src, t, -1e4, 1e4);
      });
  add("spread", Kind::Vector, "launch velocity spread in m/s, each 0..1e4 [" + vec(d.spread) + "]",
      [&s](const std::string& src, const std::string& t) { s.spread = parseVec3(src, t, 0, 1e4); });
  add("mass", Kind::Number, "particle mass in kg, 1e-6..1e6 [" + f(d.mass) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.mass = static_cast<float>(parseNumber(src, t, 1e-6, 1e6));
      });
  add("wind", Kind::Vector, "wind force in N, each -1e4..1e4 [" + vec(d.wind) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.wind = parseVec3(src, t, -1e4, 1e4);
      });
  add("drag", Kind::Number, "linear drag in N s/m, 0..1e4 [" + f(d.drag) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.drag = static_cast<float>(parseNumber(src, t, 0, 1e4));
      });
  add("seed", Kind::Number, "random seed, 0..4294967295 [" + std::to_string(d.seed) + "]",
      [&s](const std::string& src, const std::string& t) {
        s.seed = static_cast<uint32_t>(parseInteger(src, t, 0, 0xffffffffu));
      });
  add("device", Kind::Number, "Vulkan device index from 'lava info' [best; or LAVA_DEVICE]",
      [&device](const std::string& src, const std::string& t) {
        device = static_cast<unsigned>(parseInteger(src, t, 0, 255));
      });
}

}  // namespace lava::app
