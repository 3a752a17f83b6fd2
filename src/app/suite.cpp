#include "suite.h"

#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/toml_text.h"
#include "host/output.h"
#include "lava/error.h"
#include "lava/validation.h"
#include "module_scenes.h"
#include "paths.h"

namespace lava::app {
namespace {

std::string folderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

uint64_t integer(const std::string& where, const toml::node& node, uint64_t lo, uint64_t hi) {
  const auto value = node.as_integer();
  if (!value || value->get() < int64_t(lo) || uint64_t(value->get()) > hi)
    throw UsageError(where + ": expected an integer in [" + std::to_string(lo) + ", " +
                           std::to_string(hi) + "]");
  return uint64_t(value->get());
}

std::string xmlEscaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

Case named(const std::string& name, Scene scene, uint64_t steps = 3000) {
  Case c;
  c.name = name;
  c.scene = std::move(scene);
  c.steps = steps;
  c.every = steps / 3;
  return c;
}

// The builtin cases' common ground: 20,000 slots of a lively fountain.
Scene busy() {
  Scene s;
  Emitter& e = s.emitters[0];
  e.particles = 20000;
  e.rate = 7000.0;
  e.position = {0.0f, 1.0f, 0.0f};
  e.spread = {1.5f, 1.5f, 1.5f};
  return s;
}

// The CPU reference with one bit wrong from step `at` on (see Case::canary).
class Canary final : public Simulation {
 public:
  Canary(const Scene& scene, uint64_t at, unsigned threads)
      : Simulation(scene), inner_(scene, threads), at_(at) {}
  void advance(uint64_t steps) override {
    const uint64_t step = inner_.view().step;
    if (step >= at_ || step + steps < at_) return inner_.advance(steps);
    inner_.advance(at_ - step);
    State s = inner_.state();
    for (Particle& p : s.particles)
      if (p.age >= 0.0f) {
        p.vy = std::nextafter(p.vy, 1e30f);
        break;
      }
    inner_.setState(s);
    inner_.advance(step + steps - at_);
  }
  State state() override { return inner_.state(); }
  void setState(const State& state) override { inner_.setState(state); }
  std::string name() const override { return "cpu reference with a canary"; }

 private:
  CpuSimulation inner_;
  uint64_t at_;
};

}  // namespace

std::unique_ptr<Simulation> referenceFor(const Scene& scene, std::optional<uint64_t> canary,
                                         unsigned threads, CpuKernel kernel) {
  if (canary) return std::make_unique<Canary>(scene, *canary, threads);
  return std::make_unique<CpuSimulation>(scene, threads, kernel);
}

const char* statusName(Status status) {
  switch (status) {
    case Status::Pass:
      return "Pass";
    case Status::Fail:
      return "Fail";
    case Status::ExpectedFail:
      return "ExpectedFail";
    case Status::UnexpectedPass:
      return "UnexpectedPass";
  }
  return "?";
}

namespace {

// A TOML basic string (a key or a value).
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    if (static_cast<unsigned char>(ch) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\u%04x", unsigned(ch));
      out += escaped;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// A scalar of a case's scene keys as TOML (toml++'s own formatter takes the log of a float's
// magnitude into an unsigned: undefined for one below 1, fuzz/regressions/suite/).
std::string scalarToml(const toml::node& node) {
  if (const auto* f = node.as_floating_point()) {
    char text[40];
    std::snprintf(text, sizeof(text), "%.17g", f->get());
    std::string out = text;
    if (out.find_first_of(".eEn") == std::string::npos) out += ".0";  // a float, -0.0 too
    return out;
  }
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* s = node.as_string()) return quoted(s->get());
  if (const auto* a = node.as_array()) {
    std::string out = "[";
    for (size_t k = 0; k < a->size(); ++k) out += (k ? ", " : "") + scalarToml(*a->get(k));
    return out + "]";
  }
  return "{}";  // an inline table: parseScene names the key it does not take
}

// A case's scene keys as a scene file: its values, then its arrays of tables
// ([[emitter]], [[force]], [[collider]]).
std::string caseToml(const toml::table& table) {
  std::string values, tables;
  for (const auto& [key, node] : table) {
    const std::string name = quoted(std::string(key.str()));
    const toml::array* array = node.as_array();
    if (array && array->is_array_of_tables() && !array->empty()) {
      for (const toml::node& entry : *array) {
        tables += "\n[[" + name + "]]\n";
        for (const auto& [k, v] : *entry.as_table())
          tables += quoted(std::string(k.str())) + " = " + scalarToml(v) + "\n";
      }
    } else {
      values += name + " = " + scalarToml(node) + "\n";
    }
  }
  return values + tables;
}

// The suite file as TOML; a line not valid TOML or holding a character outside ASCII fails.
toml::table suiteTable(const std::string& text, const std::string& path) {
  toml::table root;
  try {
    root = toml::parse(common::asciiForToml(text), path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    if (common::errorIsNonAscii(text, where.line, where.column, e.description()))
      throw UsageError("--suite: " + path + ":" + std::to_string(where.line) +
                       ": a character outside ASCII (only comments may hold one)");
    throw UsageError("--suite: " + path + ":" + std::to_string(e.source().begin.line) +
                           ": not valid TOML (" + std::string(e.description()) + ")");
  }
  return root;
}

// Whether the table's string `key` held a character outside ASCII (now '~', see asciiForToml).
bool heldNonAscii(const toml::table& table, const std::string& text, const char* key) {
  const toml::node* node = table.get(key);
  if (!node || !node->is_string()) return false;
  const toml::source_region& r = node->source();
  return common::nonAsciiBetween(text, r.begin.line, r.begin.column, r.end.line, r.end.column);
}

// A case's keys other than its scene's (name, steps, ...), checked in that order; names
// gathers the names so far, which no two cases share.
Case caseMeta(const toml::table& table, const std::string& text, const std::string& at,
              std::set<std::string>& names) {
  Case c;
  const auto name = table["name"].value<std::string>();
  if (!name || name->empty() || name->find_first_of(",\n\"") != std::string::npos ||
      heldNonAscii(table, text, "name"))
    throw UsageError(at + ".name: expected a name of ASCII characters without commas or quotes");
  c.name = *name;
  if (!names.insert(c.name).second) throw UsageError(at + ".name: '" + c.name + "' is used twice");
  const toml::node* steps = table.get("steps");
  if (!steps) throw UsageError(at + ".steps: required");
  c.steps = integer(at + ".steps", *steps, 1, 1000000000);
  if (const toml::node* every = table.get("every"))
    c.every = integer(at + ".every", *every, 1, 1000000000);
  if (const toml::node* tolerance = table.get("tolerance-ulp"))
    c.toleranceUlp = uint32_t(integer(at + ".tolerance-ulp", *tolerance, 0, 0x80000000u));
  if (const toml::node* serial = table.get("start-serial"))
    c.startSerial = integer(at + ".start-serial", *serial, 0, uint64_t(INT64_MAX));
  if (const toml::node* canary = table.get("canary"))
    c.canary = integer(at + ".canary", *canary, 1, c.steps);
  return c;
}

// A case's scene, checked: the file its `scene` key names, or its remaining keys as a scene.
Scene caseScene(const toml::table& table, const std::string& text, const std::string& path,
                const std::string& at) {
  try {
    Scene scene;
    if (const toml::node* file = table.get("scene")) {
      const auto sceneFile = file->value<std::string>();
      if (!sceneFile || sceneFile->empty() || table.size() != 1 ||
          heldNonAscii(table, text, "scene"))
        throw UsageError(at +
                         ".scene: expected a file name of ASCII characters, and no scene "
                         "keys beside it");
      scene = loadScene(sceneFile->front() == '/' ? *sceneFile : folderOf(path) + "/" + *sceneFile);
    } else {
      scene = parseScene(caseToml(table), at);
    }
    checkScene(scene);
    return scene;
  } catch (const InvalidArgument& e) {
    throw UsageError((e.parameter().rfind(at, 0) == 0 ? "" : at + ": ") + std::string(e.what()));
  }
}

}  // namespace

std::vector<Case> loadSuite(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw UsageError("--suite: cannot read '" + path + "' (or give 'builtin')");
  std::stringstream contents;
  contents << file.rdbuf();
  return parseSuite(contents.str(), path);
}

std::vector<Case> parseSuite(const std::string& text, const std::string& path) {
  const toml::table root = suiteTable(text, path);
  for (const auto& [key, node] : root)
    if (key.str() != "case")
      throw UsageError("--suite: " + path + ": " + std::string(key.str()) +
                             ": unknown key (a suite holds [[case]] tables)");
  const toml::array* cases = root["case"].as_array();
  if (!cases || !cases->is_array_of_tables() || cases->empty())
    throw UsageError("--suite: " + path + ": expected [[case]] tables");
  std::vector<Case> out;
  std::set<std::string> names;
  for (size_t i = 0; i < cases->size(); ++i) {
    toml::table table = *(*cases)[i].as_table();
    const std::string at = path + ": case[" + std::to_string(i) + "]";
    Case c = caseMeta(table, text, at, names);
    for (const char* meta : {"name", "steps", "every", "tolerance-ulp", "start-serial", "canary"})
      table.erase(meta);
    c.scene = caseScene(table, text, path, at);
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<Case> builtinSuite(const Device& device) {
  std::vector<Case> cases;
  cases.push_back(named("seed-scene", Scene{}));
  // Each module on its own and all of them together: the scenes the tests run.
  for (const scenes::ModuleScene& m : scenes::kModuleScenes)
    cases.push_back(named(m.name, parseScene(m.toml, std::string(m.name) + ".toml")));
  {
    Scene s = busy();
    s.emitters[0].particles = 97;
    s.emitters[0].rate = 64000.0;  // 64 births per step into 97 slots: many wraps per dispatch
    cases.push_back(named("ring-wraps-within-a-dispatch", s));
    s = busy();
    s.emitters[0].rate = 3333.3;
    cases.push_back(named("fractional-rate", s));
    s = Scene{};
    s.gravity = 0.0f;
    s.drag = 5.0f;
    s.dt = 0.01;
    s.emitters[0].velocity = {1.0f, 1.0f, 1.0f};
    s.emitters[0].rate = 100.0;
    cases.push_back(named("denormals-flushed", s, 2000));
    s = busy();
    s.emitters[0].rate = 50000.0;
    Case serial = named("serial-crosses-2^32", s, 300);
    serial.startSerial = (uint64_t{1} << 32) - 5000;
    cases.push_back(serial);
  }
  {
    // Past what one binding holds on the least device (maxStorageBufferRange's minimum,
    // 2^27 bytes: 2^22 particles), in chunks no larger on any device.
    constexpr uint32_t kLeastBinding = uint32_t{1} << 22;
    Scene s;
    s.emitters[0].particles = kLeastBinding + 4096;
    s.emitters[0].burst = s.emitters[0].particles;
    Case beyond = named("beyond-one-binding", s, 6);
    beyond.chunkParticles = kLeastBinding;
    if (s.particles() <= device.maxParticles()) cases.push_back(beyond);
  }
  return cases;
}

Recording readRecording(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw UsageError("--against: cannot read '" + path + "'");
  Recording out;
  std::string line;
  std::getline(file, line);
  if (line != "case,step,hash")
    throw UsageError("--against: " + path + ": expected the header case,step,hash");
  for (int number = 2; std::getline(file, line); ++number) {
    if (line.empty()) continue;
    const size_t a = line.find(','), b = line.rfind(',');
    char* end = nullptr;
    if (a == std::string::npos || a == b)
      throw UsageError("--against: " + path + ":" + std::to_string(number) +
                             ": expected case,step,hash");
    const uint64_t step = std::strtoull(line.c_str() + a + 1, &end, 10);
    const uint64_t hash = std::strtoull(line.c_str() + b + 1, &end, 16);
    if (*end != '\0')
      throw UsageError("--against: " + path + ":" + std::to_string(number) +
                             ": expected a hexadecimal hash");
    out[line.substr(0, a)][step] = hash;
  }
  return out;
}

std::string recordingText(const std::vector<CaseResult>& results) {
  std::string out = "case,step,hash\n";
  char line[256];
  for (const CaseResult& r : results)
    for (const auto& [step, hash] : r.hashes) {
      std::snprintf(line, sizeof(line), "%s,%llu,%016llx\n", r.name.c_str(),
                    static_cast<unsigned long long>(step), static_cast<unsigned long long>(hash));
      out += line;
    }
  return out;
}

std::set<std::string> readBaseline(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw UsageError("--baseline: cannot read '" + path + "'");
  std::set<std::string> failing;
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    if (comma == std::string::npos || line.substr(comma + 1) != "Fail")
      throw UsageError("--baseline: " + path + ":" + std::to_string(number) +
                             ": expected 'case,Fail', got '" + line + "'");
    failing.insert(line.substr(0, comma));
  }
  return failing;
}

std::string resultsCsv(const std::vector<CaseResult>& results) {
  std::string out = "case,status,steps,first_divergent_step,max_ulp,seconds\n";
  char line[256];
  for (const CaseResult& r : results) {
    std::snprintf(line, sizeof(line), "%s,%s,%llu,%s,%u,%.3f\n", r.name.c_str(),
                  statusName(r.status), static_cast<unsigned long long>(r.steps),
                  r.firstDivergentStep ? std::to_string(*r.firstDivergentStep).c_str() : "",
                  r.maxUlp, r.seconds);
    out += line;
  }
  return out;
}

std::string junitXml(const std::vector<CaseResult>& results, const std::string& device,
                     const std::string& driver, const std::string& floatControls) {
  size_t failures = 0;
  double seconds = 0.0;
  for (const CaseResult& r : results) {
    failures += r.status == Status::Fail || r.status == Status::UnexpectedPass;
    seconds += r.seconds;
  }
  std::ostringstream out;
  char time[32];
  std::snprintf(time, sizeof(time), "%.3f", seconds);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites name=\"lava validate\" tests=\"" << results.size() << "\" failures=\""
      << failures << "\" time=\"" << time << "\">\n"
      << "  <testsuite name=\"lava\" tests=\"" << results.size() << "\" failures=\"" << failures
      << "\" errors=\"0\" skipped=\"0\" time=\"" << time << "\">\n"
      << "    <properties>\n"
      << "      <property name=\"device\" value=\"" << xmlEscaped(device) << "\"/>\n"
      << "      <property name=\"driver\" value=\"" << xmlEscaped(driver) << "\"/>\n"
      << "      <property name=\"float-controls\" value=\"" << xmlEscaped(floatControls) << "\"/>\n"
      << "    </properties>\n";
  for (const CaseResult& r : results) {
    std::snprintf(time, sizeof(time), "%.3f", r.seconds);
    out << "    <testcase classname=\"lava.validate\" name=\"" << xmlEscaped(r.name) << "\" time=\""
        << time << "\"";
    if (r.status == Status::Fail || r.status == Status::UnexpectedPass) {
      out << ">\n      <failure message=\"" << xmlEscaped(r.message) << "\" type=\""
          << statusName(r.status) << "\">" << xmlEscaped(r.message) << "</failure>\n"
          << "    </testcase>\n";
    } else if (r.status == Status::ExpectedFail) {
      out << ">\n      <system-out>expected to fail (baseline): " << xmlEscaped(r.message)
          << "</system-out>\n    </testcase>\n";
    } else {
      out << "/>\n";
    }
  }
  out << "  </testsuite>\n</testsuites>\n";
  return out.str();
}

std::string divergenceMessage(const ValidationReport& report, uint32_t toleranceUlp) {
  uint32_t maxUlp = 0;
  for (const Checkpoint& c : report.checkpoints) maxUlp = std::max(maxUlp, c.comparison.maxUlp);
  std::string text =
      "max ULP " + std::to_string(maxUlp) + " > tolerance " + std::to_string(toleranceUlp);
  if (report.firstDivergentStep)
    text += "; first divergent step " + std::to_string(*report.firstDivergentStep);
  if (report.firstDifference) {
    const Difference& d = *report.firstDifference;
    char detail[200];
    std::snprintf(detail, sizeof(detail),
                  ": particle %llu (emitter %u) field %s: gpu 0x%08x, cpu 0x%08x",
                  static_cast<unsigned long long>(d.particle), d.emitter, fieldName(d.field),
                  d.subjectBits, d.referenceBits);
    text += detail;
  }
  return text;
}

}  // namespace lava::app
