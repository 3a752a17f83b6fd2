#include <algorithm>
#include "keys.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "lava/error.h"
#include "lava/scene_keys.h"

namespace lava::detail {
namespace {

// Non-zero parameters keep their magnitude in [2^-20, 2^20]: products and quotients of
// scene constants then stay far from float32 denormals and overflow.
constexpr double kSmallest = 1.0 / 1048576.0;
constexpr double kLargest = 1048576.0;

struct Range {
  double lo;
  double hi;
  bool loOpen = false;    // lo itself is not accepted
  bool magnitude = true;  // the [2^-20, 2^20] rule for non-zero values
};

std::string trim(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

bool readDouble(const std::string& text, double& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return *end == '\0' && errno != ERANGE && std::isfinite(value);
}

std::string describe(const Range& r) {
  std::string text = "a number in " + std::string(r.loOpen ? "(" : "[") + formatDouble(r.lo) +
                     ", " + formatDouble(r.hi) + "]";
  if (r.magnitude) text += ", 0 or at least 2^-20 in magnitude";
  return text;
}

void checkNumber(const std::string& parameter, double value, const Range& r,
                 const std::string& given) {
  const bool ok = std::isfinite(value) && value >= r.lo && value <= r.hi &&
                  !(r.loOpen && value == r.lo) &&
                  !(r.magnitude && value != 0.0 &&
                    (std::fabs(value) < kSmallest || std::fabs(value) > kLargest));
  if (!ok) throw InvalidArgument(parameter, "expected " + describe(r) + ", got '" + given + "'");
}

double parseNumber(const std::string& parameter, const std::string& text, const Range& r) {
  double value = 0.0;
  if (!readDouble(text, value))
    throw InvalidArgument(parameter, "expected " + describe(r) + ", got '" + text + "'");
  checkNumber(parameter, value, r, text);
  return value;
}

uint64_t parseInteger(const std::string& parameter, const std::string& text, uint64_t lo,
                      uint64_t hi) {
  const std::string expected =
      "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  double value = 0.0;
  if (!readDouble(text, value) || value != std::floor(value) || value < double(lo) ||
      value > double(hi))
    throw InvalidArgument(parameter, expected + ", got '" + text + "'");
  if (text.find_first_not_of("0123456789") == std::string::npos)
    return std::strtoull(text.c_str(), nullptr, 10);  // exact beyond 2^53
  return static_cast<uint64_t>(value);
}

Vec3 parseVector(const std::string& parameter, const std::string& text, const Range& r) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');) parts.push_back(trim(part));
  if (parts.size() != 3 || text.empty() || text.back() == ',')
    throw InvalidArgument(parameter, "expected 3 comma-separated numbers X,Y,Z, each " +
                                         describe(r) + ", got '" + text + "'");
  float v[3];
  for (int i = 0; i < 3; ++i)
    v[i] =
        static_cast<float>(parseNumber(parameter + " (component " + "xyz"[i] + ")", parts[i], r));
  return {v[0], v[1], v[2]};
}

std::string vectorText(const Vec3& v) {
  return formatFloat(v.x) + "," + formatFloat(v.y) + "," + formatFloat(v.z);
}

// Key factories: `get(scene, where)` returns the field.
template <typename Get>
KeyDef floatKey(const char* name, const char* help, Range r, Get get) {
  KeyDef d;
  d.key = {name, KeyKind::Number, std::string(help) + "; " + describe(r), ""};
  d.set = [r, get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    get(s, i) = static_cast<float>(parseNumber(p, t, r));
  };
  d.check = [r, get](const Scene& s, size_t i, const std::string& p) {
    const float v = get(const_cast<Scene&>(s), i);
    checkNumber(p, v, r, formatFloat(v));
  };
  d.text = [get](const Scene& s, size_t i) { return formatFloat(get(const_cast<Scene&>(s), i)); };
  return d;
}

template <typename Get>
KeyDef doubleKey(const char* name, const char* help, Range r, Get get) {
  KeyDef d;
  d.key = {name, KeyKind::Number, std::string(help) + "; " + describe(r), ""};
  d.set = [r, get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    get(s, i) = parseNumber(p, t, r);
  };
  d.check = [r, get](const Scene& s, size_t i, const std::string& p) {
    const double v = get(const_cast<Scene&>(s), i);
    checkNumber(p, v, r, formatDouble(v));
  };
  d.text = [get](const Scene& s, size_t i) { return formatDouble(get(const_cast<Scene&>(s), i)); };
  return d;
}

template <typename Get>
KeyDef countKey(const char* name, const char* help, uint64_t lo, uint64_t hi, Get get) {
  KeyDef d;
  d.key = {name, KeyKind::Integer,
           std::string(help) + "; an integer in [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]",
           ""};
  d.set = [lo, hi, get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    get(s, i) = static_cast<uint32_t>(parseInteger(p, t, lo, hi));
  };
  d.check = [lo, hi, get](const Scene& s, size_t i, const std::string& p) {
    const uint64_t v = get(const_cast<Scene&>(s), i);
    if (v < lo || v > hi)
      throw InvalidArgument(p, "expected an integer in [" + std::to_string(lo) + ", " +
                                   std::to_string(hi) + "], got " + std::to_string(v));
  };
  d.text = [get](const Scene& s, size_t i) {
    return std::to_string(get(const_cast<Scene&>(s), i));
  };
  return d;
}

template <typename Get>
KeyDef vectorKey(const char* name, const char* help, Range r, Get get) {
  KeyDef d;
  d.key = {name, KeyKind::Vector, std::string(help) + "; X,Y,Z each " + describe(r), ""};
  d.set = [r, get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    get(s, i) = parseVector(p, t, r);
  };
  d.check = [r, get](const Scene& s, size_t i, const std::string& p) {
    const Vec3 v = get(const_cast<Scene&>(s), i);
    const float c[3] = {v.x, v.y, v.z};
    for (int k = 0; k < 3; ++k)
      checkNumber(p + " (component " + "xyz"[k] + ")", c[k], r, formatFloat(c[k]));
  };
  d.text = [get](const Scene& s, size_t i) { return vectorText(get(const_cast<Scene&>(s), i)); };
  return d;
}

// An enum key whose values are named by lava::name(E) for E(0) .. E(count - 1).
template <typename E, typename Get>
KeyDef nameKey(const char* key, const char* help, uint32_t count, Get get) {
  KeyDef d;
  std::string names;
  for (uint32_t k = 0; k < count; ++k) names += std::string(k ? ", " : "") + name(E(k));
  d.key = {key, KeyKind::Name, std::string(help) + "; one of " + names, ""};
  d.set = [count, get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    std::string accepted;
    for (uint32_t k = 0; k < count; ++k) {
      if (t == name(E(k))) {
        get(s, i) = E(k);
        return;
      }
      accepted += std::string(k ? ", " : "") + name(E(k));
    }
    throw InvalidArgument(p, "expected one of " + accepted + ", got '" + t + "'");
  };
  d.check = [count, get](const Scene& s, size_t i, const std::string& p) {
    if (uint32_t(get(const_cast<Scene&>(s), i)) >= count)
      throw InvalidArgument(p, "not a known value");
  };
  d.text = [get](const Scene& s, size_t i) {
    return std::string(name(get(const_cast<Scene&>(s), i)));
  };
  return d;
}

template <typename Get>
KeyDef flagKey(const char* key, const char* help, Get get) {
  KeyDef d;
  d.key = {key, KeyKind::Flag, std::string(help) + "; true or false", ""};
  d.set = [get](Scene& s, size_t i, const std::string& p, const std::string& t) {
    if (t != "true" && t != "false")
      throw InvalidArgument(p, "expected true or false, got '" + t + "'");
    get(s, i) = t == "true";
  };
  d.check = [](const Scene&, size_t, const std::string&) {};
  d.text = [get](const Scene& s, size_t i) {
    return std::string(get(const_cast<Scene&>(s), i) ? "true" : "false");
  };
  return d;
}

const Range kUnit{0.0, 1.0};
const Range kPosition{-1e4, 1e4};
const Range kLength{0.0, 1e4};
const Range kPositiveLength{0.0, 1e4, true};
const Range kTemperature{0.0, 1e5};

std::vector<KeyDef> emitterKeys(bool flat) {
  // Flat (top-level) keys reach emitter 0 under the format 1 names.
  auto e = [flat](Scene& s, size_t i) -> Emitter& { return s.emitters.at(flat ? 0 : i); };
  std::vector<KeyDef> keys = {
      countKey("particles", "ring capacity (slots)", 1, uint64_t{1} << 31,
               [e](Scene& s, size_t i) -> uint32_t& { return e(s, i).particles; }),
      doubleKey("rate", "births per second", {0.0, 1e9, false, false},
                [e](Scene& s, size_t i) -> double& { return e(s, i).rate; }),
      countKey("burst", "extra births at step 0 and every burst-interval", 0, uint64_t{1} << 31,
               [e](Scene& s, size_t i) -> uint32_t& { return e(s, i).burst; }),
      doubleKey("burst-interval", "seconds between bursts (0: step 0 only)", {0.0, 1e6},
                [e](Scene& s, size_t i) -> double& { return e(s, i).burstInterval; }),
      nameKey<Shape>("shape", "where births are placed", 4,
                     [e](Scene& s, size_t i) -> Shape& { return e(s, i).shape; }),
      vectorKey(flat ? "emitter" : "position", "emitter centre (m)", kPosition,
                [e](Scene& s, size_t i) -> Vec3& { return e(s, i).position; }),
      floatKey(flat ? "emitter-radius" : "radius", "disc or sphere radius (m)", kLength,
               [e](Scene& s, size_t i) -> float& { return e(s, i).radius; }),
      vectorKey("velocity", "mean launch velocity (m/s)", kPosition,
                [e](Scene& s, size_t i) -> Vec3& { return e(s, i).velocity; }),
      vectorKey("spread", "launch velocity spread per component (m/s)", kLength,
                [e](Scene& s, size_t i) -> Vec3& { return e(s, i).spread; }),
      floatKey("mass", "particle mass (kg)", {0.0, 1e6, true},
               [e](Scene& s, size_t i) -> float& { return e(s, i).mass; }),
      floatKey("lifetime", "seconds a particle lives (0: until its slot is reborn)", {0.0, 1e6},
               [e](Scene& s, size_t i) -> float& { return e(s, i).lifetime; }),
  };
  if (!flat) {  // a box's half-extents have no top-level key (`size` is the image size there)
    keys.push_back(vectorKey("size", "box half-extents (m)", kLength,
                             [e](Scene& s, size_t i) -> Vec3& { return e(s, i).size; }));
    keys.push_back(flagKey("flow", "its particles are the flow's ([flow])",
                           [e](Scene& s, size_t i) -> bool& { return e(s, i).flow; }));
    keys.push_back(floatKey("temperature", "flow particles' temperature at birth (K; 0: [flow]'s)",
                            kTemperature,
                            [e](Scene& s, size_t i) -> float& { return e(s, i).temperature; }));
    keys.push_back(nameKey<Fill>(
        "fill",
        "where a flow emitter's births go: random in its shape, launched; or lattice, one "
        "burst at rest on the cubic lattice of spacing (mass/density)^(1/3) centred in its "
        "box, sphere or disc",
        2, [e](Scene& s, size_t i) -> Fill& { return e(s, i).fill; }));
    for (size_t k = keys.size() - 3; k < keys.size(); ++k) keys[k].flowOnly = true;
  }
  for (KeyDef& k : keys) k.emitterZero = flat;
  return keys;
}

std::vector<KeyDef> topKeys() {
  std::vector<KeyDef> keys = {
      doubleKey("dt", "step h (s)", {1e-6, 1.0}, [](Scene& s, size_t) -> double& { return s.dt; }),
      floatKey("gravity", "g along -y (m/s^2)", {-1000.0, 1000.0},
               [](Scene& s, size_t) -> float& { return s.gravity; }),
      floatKey("restitution", "ground: normal speed kept by a bounce", kUnit,
               [](Scene& s, size_t) -> float& { return s.restitution; }),
      floatKey("friction", "ground: tangential velocity kept by a bounce", kUnit,
               [](Scene& s, size_t) -> float& { return s.friction; }),
      vectorKey("wind", "wind force (N)", kPosition,
                [](Scene& s, size_t) -> Vec3& { return s.wind; }),
      floatKey("drag", "linear drag (N s/m)", kLength,
               [](Scene& s, size_t) -> float& { return s.drag; }),
      countKey("seed", "random seed (emitter k uses seed + k)", 0, 0xffffffffu,
               [](Scene& s, size_t) -> uint32_t& { return s.seed; }),
      floatKey("line-scale", "drawn line from x to x + s v (s)", {0.0, 10.0},
               [](Scene& s, size_t) -> float& { return s.lineScale; }),
      nameKey<Integrator>("integrator", "how a step advances x and v", 3,
                          [](Scene& s, size_t) -> Integrator& { return s.integrator; }),
  };
  for (KeyDef& k : emitterKeys(true)) keys.push_back(std::move(k));
  return keys;
}

std::vector<KeyDef> forceKeys() {
  auto f = [](Scene& s, size_t i) -> Force& { return s.forces.at(i); };
  return {
      nameKey<ForceType>("type", "attractor or vortex", 2,
                         [f](Scene& s, size_t i) -> ForceType& { return f(s, i).type; }),
      vectorKey("position", "attractor point or vortex axis point (m)", kPosition,
                [f](Scene& s, size_t i) -> Vec3& { return f(s, i).position; }),
      vectorKey("axis", "vortex axis (not normalised)", kPosition,
                [f](Scene& s, size_t i) -> Vec3& { return f(s, i).axis; }),
      floatKey("strength", "k (N/m)", kPosition,
               [f](Scene& s, size_t i) -> float& { return f(s, i).strength; }),
      floatKey("radius", "attractor range (m; 0: everywhere)", kLength,
               [f](Scene& s, size_t i) -> float& { return f(s, i).radius; }),
  };
}

std::vector<KeyDef> colliderKeys() {
  auto c = [](Scene& s, size_t i) -> Collider& { return s.colliders.at(i); };
  return {
      nameKey<ColliderType>("type", "plane, sphere, box or cone", 4,
                            [c](Scene& s, size_t i) -> ColliderType& { return c(s, i).type; }),
      vectorKey("position", "plane point, sphere or box centre, cone base centre (m)", kPosition,
                [c](Scene& s, size_t i) -> Vec3& { return c(s, i).position; }),
      vectorKey("normal", "plane normal (not 0; normalised by Lava)", kPosition,
                [c](Scene& s, size_t i) -> Vec3& { return c(s, i).normal; }),
      floatKey("radius", "sphere radius (m)", kLength,
               [c](Scene& s, size_t i) -> float& { return c(s, i).radius; }),
      vectorKey("size", "box half-extents (m)", kLength,
                [c](Scene& s, size_t i) -> Vec3& { return c(s, i).size; }),
      floatKey("base-radius", "cone radius at its base (m)", kPositiveLength,
               [c](Scene& s, size_t i) -> float& { return c(s, i).baseRadius; }),
      floatKey("top-radius", "cone radius at its top (m), at most base-radius", kLength,
               [c](Scene& s, size_t i) -> float& { return c(s, i).topRadius; }),
      floatKey("height", "cone height (m)", kPositiveLength,
               [c](Scene& s, size_t i) -> float& { return c(s, i).height; }),
      floatKey("restitution", "normal speed kept by a bounce", kUnit,
               [c](Scene& s, size_t i) -> float& { return c(s, i).restitution; }),
      floatKey("friction", "tangential velocity kept by a bounce", kUnit,
               [c](Scene& s, size_t i) -> float& { return c(s, i).friction; }),
  };
}

std::vector<KeyDef> flowKeys() {
  // A scene without a flow reads as the flow's defaults (the keys' defaults and help).
  auto f = [](Scene& s, size_t) -> Flow& {
    if (!s.flow) s.flow.emplace();
    return *s.flow;
  };
  const Range rate{0.0, 1e3};
  return {
      floatKey("radius", "h (m): flow particles closer than this interact", {0.0, 100.0, true},
               [f](Scene& s, size_t i) -> float& { return f(s, i).radius; }),
      floatKey("density", "kg/m^3 at rest: a flow particle's volume is its mass / density",
               {0.0, 1e6, true}, [f](Scene& s, size_t i) -> float& { return f(s, i).density; }),
      floatKey("temperature", "eruption temperature (K), each flow emitter's default",
               {0.0, 1e5, true},
               [f](Scene& s, size_t i) -> float& { return f(s, i).temperature; }),
      floatKey("viscosity", "kinematic viscosity (m^2/s) at and above temperature", {0.0, 1e4},
               [f](Scene& s, size_t i) -> float& { return f(s, i).viscosity; }),
      floatKey("viscosity-solidus", "kinematic viscosity (m^2/s) just above solidus, at least "
               "viscosity", {0.0, 1e4},
               [f](Scene& s, size_t i) -> float& { return f(s, i).viscositySolidus; }),
      floatKey("solidus", "K: at or below it a flow particle is solid; below temperature",
               {0.0, 1e5, true}, [f](Scene& s, size_t i) -> float& { return f(s, i).solidus; }),
      floatKey("ambient", "K: the air and the ground far away", kTemperature,
               [f](Scene& s, size_t i) -> float& { return f(s, i).ambient; }),
      floatKey("cooling-air", "1/s: dT/dt = -cooling-air (T - ambient), always", rate,
               [f](Scene& s, size_t i) -> float& { return f(s, i).coolingAir; }),
      floatKey("cooling-ground", "1/s: added while touching the ground or a collider", rate,
               [f](Scene& s, size_t i) -> float& { return f(s, i).coolingGround; }),
      floatKey("conduction", "heat diffusivity between neighbours (m^2/s; 0: none)", {0.0, 1e3},
               [f](Scene& s, size_t i) -> float& { return f(s, i).conduction; }),
      floatKey("sound-speed",
               "the explicit flow's pressure wave speed (m/s), at most 0.4 radius / dt; the "
               "implicit flow ignores it",
               {0.0, 1e4, true},
               [f](Scene& s, size_t i) -> float& { return f(s, i).soundSpeed; }),
      floatKey("restitution", "normal speed a flow particle keeps off the ground and colliders",
               kUnit, [f](Scene& s, size_t i) -> float& { return f(s, i).restitution; }),
      nameKey<FlowSolver>(
          "solver",
          "the flow's method: explicit (weakly compressible, viscosity capped; every backend) "
          "or implicit (density constraint, viscosity as given, substeps; the GPU backend steps "
          "it on the host)",
          2, [f](Scene& s, size_t i) -> FlowSolver& { return f(s, i).solver; }),
  };
}

// Fills each key's default from a default-constructed entry of its table.
std::vector<KeyDef> withDefaults(std::vector<KeyDef> keys) {
  Scene s;
  s.forces.resize(1);
  s.colliders.resize(1);
  s.flow.emplace();
  for (KeyDef& k : keys) k.key.fallback = k.text(s, 0);
  return keys;
}

}  // namespace

float defaultFlowMass(const Flow& flow) {
  const double half = 0.5 * double(flow.radius);
  return float(double(flow.density) * half * half * half);
}

std::string formatFloat(float value) {
  if (value == 0.0f && std::signbit(value)) return "-0.0";  // TOML's -0 is the integer 0
  char text[32];
  for (int digits = 6; digits <= 9; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, double(value));
    if (std::strtof(text, nullptr) == value) break;
  }
  return text;
}

std::string formatDouble(double value) {
  if (value == 0.0 && std::signbit(value)) return "-0.0";
  char text[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

const std::vector<KeyDef>& keyDefs(KeyTable table) {
  static const std::vector<KeyDef> top = withDefaults(topKeys());
  static const std::vector<KeyDef> emitter = withDefaults(emitterKeys(false));
  static const std::vector<KeyDef> force = withDefaults(forceKeys());
  static const std::vector<KeyDef> collider = withDefaults(colliderKeys());
  static const std::vector<KeyDef> flow = withDefaults(flowKeys());
  switch (table) {
    case KeyTable::Top:
      return top;
    case KeyTable::Emitter:
      return emitter;
    case KeyTable::Force:
      return force;
    case KeyTable::Flow:
      return flow;
    case KeyTable::Collider:
      break;
  }
  return collider;
}

const KeyDef* findKey(KeyTable table, const std::string& key) {
  for (const KeyDef& d : keyDefs(table))
    if (d.key.name == key) return &d;
  return nullptr;
}

std::string keyList(KeyTable table) {
  std::string list;
  for (const KeyDef& d : keyDefs(table)) list += (list.empty() ? "" : ", ") + d.key.name;
  return list;
}

std::string unknownKey(KeyTable table, const std::string& key, const std::string& extra) {
  std::vector<std::string> names;
  for (const KeyDef& d : keyDefs(table)) names.push_back(d.key.name);
  const std::string best = nearestName(key, names, 2);
  return "unknown key" + (best.empty() ? std::string() : "; did you mean " + best + "?") +
         " (accepted: " + extra + keyList(table) + ")";
}

}  // namespace lava::detail

namespace lava {

namespace {
// Levenshtein distance.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}
}  // namespace

std::string nearestName(const std::string& given, const std::vector<std::string>& names,
                        size_t maxEdits) {
  std::string normalised = given;
  std::replace(normalised.begin(), normalised.end(), '_', '-');
  std::string best;
  size_t bestDistance = maxEdits + 1;
  for (const std::string& name : names)
    if (const size_t e = editDistance(normalised, name); e < bestDistance)
      bestDistance = e, best = name;
  return best;
}

const std::vector<SceneKey>& sceneKeys(KeyTable table) {
  static const auto collect = [](KeyTable t) {
    std::vector<SceneKey> keys;
    for (const detail::KeyDef& d : detail::keyDefs(t)) keys.push_back(d.key);
    return keys;
  };
  static const std::vector<SceneKey> tables[5] = {
      collect(KeyTable::Top), collect(KeyTable::Emitter), collect(KeyTable::Force),
      collect(KeyTable::Collider), collect(KeyTable::Flow)};
  return tables[static_cast<int>(table)];
}

void setSceneKey(Scene& scene, KeyTable table, size_t where, const std::string& key,
                 const std::string& value) {
  const detail::KeyDef* def = detail::findKey(table, key);
  if (!def) throw InvalidArgument(key, detail::unknownKey(table, key));
  if (table == KeyTable::Top) {
    if (def->emitterZero && scene.emitters.empty()) scene.emitters.resize(1);
  } else if (table != KeyTable::Flow) {
    const size_t size = table == KeyTable::Emitter ? scene.emitters.size()
                        : table == KeyTable::Force ? scene.forces.size()
                                                   : scene.colliders.size();
    if (where >= size)
      throw InvalidArgument(key, "table entry " + std::to_string(where) + " does not exist");
  }
  def->set(scene, where, key, value);
}

}  // namespace lava
