// `import lava`: Lava for numpy users, on the library's public API. Parameters are
// the command line's flags with `-` written `_`; states come back as float32 arrays with
// the columns of `lava simulate --out FILE.npy` (px py pz vx vy vz age).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "common/npy.h"
#include "host/frame_renderer.h"
#include "host/series.h"
#include "lava/checkpoint.h"
#include "lava/lava.h"
#include "lava/scene_keys.h"
#include "lava/validation.h"

namespace py = pybind11;

namespace {

// Keys of the `lava` program's own options a scene file may hold for it: passed over here,
// as each command passes over the others'.
const std::set<std::string> kProgramKeys = {
    "steps",      "every",    "tolerance-ulp", "backend",    "threads",
    "out",        "csv",      "frames",        "fps",        "size",
    "warmup",     "renderer", "video",         "present",    "headless",
    "vsync",      "device",   "sizes",         "steps-per-dispatch",
    "backends",   "json",     "integrators",   "dts",        "seconds",
    "energy-csv", "suite",    "junit",         "results",    "baseline",
    "record",     "against"};

// One device per index for the life of the module (a Vulkan instance is costly to make).
// Like the program, LAVA_DEVICE picks it and LAVA_VALIDATION turns the validation layer on.
lava::Device& device(std::optional<unsigned> index) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<lava::Device>> devices;
  std::lock_guard<std::mutex> lock(mutex);
  if (!index)
    if (const char* env = std::getenv("LAVA_DEVICE"); env && *env) index = unsigned(std::atoi(env));
  const int key = index ? int(*index) : -1;
  auto& slot = devices[key];
  if (!slot) {
    lava::DeviceOptions options;
    options.index = index;
    const char* validation = std::getenv("LAVA_VALIDATION");
    options.validation = validation && *validation && std::strcmp(validation, "0") != 0;
    options.applicationName = "lava (python)";
    slot = std::make_unique<lava::Device>(options);
  }
  return *slot;
}

// Validation messages of the devices so far, as one RuntimeError (a message is a failure).
void raiseOnValidation(lava::Device& d) {
  const std::vector<std::string> messages = d.takeValidationMessages();
  if (!messages.empty())
    throw std::runtime_error("Vulkan validation: " + messages.front() +
                             (messages.size() > 1 ? " (and more)" : ""));
}

std::string pythonName(const std::string& key) {
  std::string name = key;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

// A keyword of the wrong type: lava.ArgumentTypeError, both a TypeError and a ValueError
// (bad input was a ValueError before types were told apart), its message naming the keyword.
PyObject* argumentTypeError = nullptr;

[[noreturn]] void wrongType(const std::string& name, const std::string& expected,
                            const py::handle& value) {
  const std::string got =
      std::string(Py_TYPE(value.ptr())->tp_name) + " " + py::repr(value).cast<std::string>();
  PyErr_SetString(argumentTypeError, (name + ": expected " + expected + ", got " + got).c_str());
  throw py::error_already_set();
}

bool isNumber(const py::handle& value) {
  return !py::isinstance<py::bool_>(value) && !py::isinstance<py::str>(value) &&
         PyNumber_Check(value.ptr()) && !py::hasattr(value, "__len__");
}

// An integer keyword (a Python or numpy integer, not a bool) in [lo, hi].
uint64_t integerArg(const std::string& name, const py::handle& value, uint64_t lo, uint64_t hi) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr()))
    wrongType(name, "an integer", value);
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  const unsigned long long v = PyLong_AsUnsignedLongLong(index.ptr());
  const bool overflow = PyErr_Occurred() != nullptr;
  PyErr_Clear();
  if (overflow || v < lo || v > hi)
    throw py::value_error(name + ": expected " + std::to_string(lo) + " to " + std::to_string(hi) +
                          ", got " + py::repr(value).cast<std::string>());
  return v;
}

std::string textArg(const std::string& name, const py::handle& value) {
  if (!py::isinstance<py::str>(value)) wrongType(name, "a str", value);
  return value.cast<std::string>();
}

// A file's path: a str or an os.PathLike.
std::string pathArg(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::hasattr(value, "__fspath__")) {
    const py::object path = value.attr("__fspath__")();
    if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  }
  wrongType(name, "a path (str or os.PathLike)", value);
}

// A sequence of numbers as "x,y,z" (each as Python's repr of the float).
std::string joinedNumbers(const std::string& name, const py::handle& value) {
  std::string joined;
  for (const py::handle& item : value) {
    if (!isNumber(item)) wrongType(name, "a sequence of numbers", value);
    joined += (joined.empty() ? "" : ",") + py::repr(py::float_(py::reinterpret_borrow<py::object>(item))).cast<std::string>();
  }
  return joined;
}

// A Python value as the text a scene key of `kind` reads: the program's own text (a str),
// or a value of the key's type. Wrong types raise ArgumentTypeError naming the key.
std::string keyText(const std::string& name, const py::handle& value,
                    std::optional<lava::KeyKind> kind) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  switch (kind.value_or(lava::KeyKind::Number)) {
    case lava::KeyKind::Vector:
      if (isNumber(value) || !py::hasattr(value, "__iter__"))
        wrongType(name, "a sequence of 3 numbers or 'x,y,z'", value);
      return joinedNumbers(name, value);
    case lava::KeyKind::Flag:
      if (!py::isinstance<py::bool_>(value)) wrongType(name, "a bool", value);
      return value.cast<bool>() ? "true" : "false";
    case lava::KeyKind::Name:
      wrongType(name, "a str", value);
    case lava::KeyKind::Integer:
    case lava::KeyKind::Number:
      break;
  }
  if (!isNumber(value)) wrongType(name, "a number", value);
  if (PyIndex_Check(value.ptr()))
    return py::str(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())))
        .cast<std::string>();
  return py::repr(py::float_(py::reinterpret_borrow<py::object>(value))).cast<std::string>();
}

// The kind of scene key `flag` in `table`, when it is one.
std::optional<lava::KeyKind> keyKind(lava::KeyTable table, const std::string& flag) {
  for (const lava::SceneKey& k : lava::sceneKeys(table))
    if (k.name == flag) return k.kind;
  return std::nullopt;
}

// The presets the package ships (lava/scenes/*.toml, the module scenes in scenes/modules).
std::string presetFolder() {
  const std::string init = py::module_::import("lava").attr("__file__").cast<std::string>();
  return init.substr(0, init.find_last_of('/')) + "/scenes";
}

bool isFile(const std::string& path) {
  return py::module_::import("os.path").attr("isfile")(path).cast<bool>();
}

// `value` as a scene: a lava.Scene, a TOML file's path, or a preset's name ("volcano").
lava::Scene sceneArg(const std::string& name, const py::handle& value) {
  if (py::isinstance<lava::Scene>(value)) return value.cast<lava::Scene>();
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__"))
    wrongType(name, "a lava.Scene, a preset's name or a TOML file's path", value);
  std::string path = pathArg(name, value);
  if (!isFile(path) && path.find('/') == std::string::npos) {
    const std::string stem = path.size() > 5 && path.compare(path.size() - 5, 5, ".toml") == 0
                                 ? path.substr(0, path.size() - 5)
                                 : path;
    for (const std::string& folder : {presetFolder(), presetFolder() + "/modules"})
      if (isFile(folder + "/" + stem + ".toml")) {
        path = folder + "/" + stem + ".toml";
        break;
      }
    if (!isFile(path)) {
      const py::list names = py::module_::import("lava").attr("presets")();
      throw py::value_error(name + ": '" + path + "' is no file and no preset (presets: " +
                            py::str(", ").attr("join")(names).cast<std::string>() + ")");
    }
  }
  try {
    return lava::loadScene(path, [](const std::string& key, const std::string&) {
      return kProgramKeys.count(key) > 0;
    });
  } catch (const lava::InvalidArgument& e) {
    throw py::value_error(name + ": " + e.what());
  }
}

struct Options {
  lava::Scene scene;
  std::optional<unsigned> device;
  unsigned threads = 1;
  std::optional<uint32_t> toleranceUlp;
};

// The scene file (if any), then each keyword: scene keys, device, threads, tolerance_ulp.
Options options(const py::object& scenePath, const py::kwargs& params,
                std::set<std::string> extra = {}, std::set<std::string> skip = {},
                const std::string& sceneName = "scene") {
  Options o;
  if (!scenePath.is_none()) o.scene = sceneArg(sceneName, scenePath);
  for (const auto& [key, value] : params) {
    const std::string name = key.cast<std::string>();
    if (skip.count(name)) continue;  // the caller's own keywords
    std::string flag = name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (name == "device") {
      o.device = unsigned(integerArg(name, value, 0, 255));
    } else if (name == "threads") {
      const auto threads = unsigned(integerArg(name, value, 0, 1024));
      o.threads = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    } else if (name == "tolerance_ulp" && extra.count(name)) {
      o.toleranceUlp = uint32_t(integerArg(name, value, 0, UINT32_MAX));
    } else {
      try {
        lava::setSceneKey(o.scene, lava::KeyTable::Top, 0, flag,
                          keyText(name, value, keyKind(lava::KeyTable::Top, flag)));
      } catch (const lava::InvalidArgument& e) {
        if (e.detail().rfind("unknown key", 0) == 0) {
          std::string accepted;
          for (const lava::SceneKey& k : lava::sceneKeys(lava::KeyTable::Top))
            accepted += (accepted.empty() ? "" : ", ") + pythonName(k.name);
          throw py::value_error("unknown parameter '" + name + "' (accepted: " + accepted +
                                ", device, threads" + (extra.empty() ? "" : ", tolerance_ulp") +
                                ")");
        }
        throw py::value_error(name + ": " + e.detail());
      }
    }
  }
  try {
    lava::checkScene(o.scene);
  } catch (const lava::InvalidArgument& e) {
    throw py::value_error(e.what());
  }
  return o;
}

// The state as the .npy columns: px py pz vx vy vz age (-1: not alive), and temperature (K)
// for a scene with a flow.
py::array_t<float> columns(const lava::State& state) {
  const size_t n = lava::common::stateColumns(state);
  py::array_t<float> out({py::ssize_t(state.particles.size()), py::ssize_t(n)});
  auto rows = out.mutable_unchecked<2>();
  for (size_t i = 0; i < state.particles.size(); ++i) {
    float row[8];
    lava::common::stateRow(state, i, row);
    for (size_t c = 0; c < n; ++c) rows(py::ssize_t(i), py::ssize_t(c)) = row[c];
  }
  return out;
}

std::unique_ptr<lava::Simulation> make(const std::string& backend, const Options& o) {
  if (backend == "gpu") return std::make_unique<lava::GpuSimulation>(device(o.device), o.scene);
  if (backend == "cpu") return std::make_unique<lava::CpuSimulation>(o.scene, o.threads);
  if (backend == "cpu-simd")
    return std::make_unique<lava::CpuSimulation>(o.scene, o.threads, lava::CpuKernel::Simd);
  throw py::value_error("backend: expected 'gpu', 'cpu' or 'cpu-simd', got '" + backend + "'");
}

// Raises KeyboardInterrupt (or what a signal handler raised) once Ctrl-C was pressed.
void checkSignals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// Runs `steps` steps without the GIL, in batches, looking for Ctrl-C between them: an
// interrupted run stops at a whole step, its state consistent.
void advanceInterruptibly(lava::Simulation& sim, uint64_t steps) {
  constexpr uint64_t kBatch = 1024;
  while (steps > 0) {
    const uint64_t batch = std::min(steps, kBatch);
    {
      py::gil_scoped_release release;
      sim.advance(batch);
    }
    steps -= batch;
    checkSignals();
  }
}

uint64_t stepOf(lava::Simulation& sim) {
  if (auto* cpu = dynamic_cast<lava::CpuSimulation*>(&sim)) return cpu->view().step;
  return static_cast<lava::GpuSimulation&>(sim).step();
}

// Runs `steps` steps writing a sample every `every` steps into `folder`, as `lava simulate
// --series` does (docs/cli.md, "Series"): from step 0 a new series; from a later step the
// series in `folder` continued, its samples before this step kept.
void advanceWithSeries(lava::Simulation& sim, const std::string& folder, uint64_t steps,
                       uint64_t every) {
  const uint64_t first = stepOf(sim);
  lava::host::SeriesWriter series(folder, every, first, first > 0);
  series.sampleIfDue(sim);
  series.advance(sim, steps, advanceInterruptibly);
}

// series= and every= of simulate(): both or neither.
std::optional<std::pair<std::string, uint64_t>> seriesArgs(const py::object& series,
                                                           const py::object& every) {
  if (series.is_none() && every.is_none()) return std::nullopt;
  if (every.is_none()) throw py::value_error("every: series= needs every=K, the steps between samples");
  const uint64_t k = integerArg("every", every, 1, 1000000000);
  if (series.is_none()) throw py::value_error("every: needs series=FOLDER");
  return std::make_pair(pathArg("series", series), k);
}

// A running simulation for scripts: advance it, look at it, save and resume it.
class Simulation {
 public:
  Simulation(const py::object& scene, const py::object& backend, const py::kwargs& params)
      : options_(options(scene, params)),
        backend_(textArg("backend", backend)),
        sim_(make(backend_, options_)) {}
  Simulation(Options o, const std::string& backend)
      : options_(std::move(o)), backend_(backend), sim_(make(backend, options_)) {}

  void advance(const py::object& steps) {
    advanceInterruptibly(*sim_, integerArg("steps", steps, 0, uint64_t{1} << 40));
    validated();
  }
  void writeSeries(const py::object& folder, const py::object& steps, const py::object& every) {
    advanceWithSeries(*sim_, pathArg("folder", folder), integerArg("steps", steps, 0, uint64_t{1} << 40),
                      integerArg("every", every, 1, 1000000000));
    validated();
  }
  py::array_t<float> state() {
    const lava::State state = sim_->state();
    validated();
    return columns(state);
  }
  // Raw slots (particles, 8), as `particles` gives them; step and clocks stay.
  void setState(const py::object& particles) {
    using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;
    if (isNumber(particles) || py::isinstance<py::str>(particles) ||
        !py::hasattr(particles, "__len__"))
      wrongType("particles", "a float32 array (particles, 8)", particles);
    const Floats raw = Floats::ensure(particles);
    if (!raw) {
      PyErr_Clear();
      wrongType("particles", "a float32 array (particles, 8)", particles);
    }
    lava::State state = sim_->state();
    if (raw.ndim() != 2 || raw.shape(1) != 8 || size_t(raw.shape(0)) != state.particles.size())
      throw py::value_error("particles: expected float32 (" +
                            std::to_string(state.particles.size()) + ", 8), as `particles` is");
    std::memcpy(state.particles.data(), raw.data(), state.particles.size() * sizeof(lava::Particle));
    sim_->setState(state);
    validated();
  }
  void checkpoint(const py::object& path) {
    const std::string file = pathArg("path", path);
    const lava::State state = sim_->state();
    lava::writeCheckpoint(file, sim_->scene(), state);
    validated();
  }
  uint64_t step() { return stepOf(*sim_); }
  const lava::Scene& scene() const { return sim_->scene(); }
  lava::CpuSimulation* cpu() { return dynamic_cast<lava::CpuSimulation*>(sim_.get()); }
  lava::Simulation& simulation() { return *sim_; }
  const std::string& backend() const { return backend_; }

 private:
  void validated() {
    if (backend_ == "gpu") raiseOnValidation(device(options_.device));
  }

  Options options_;
  std::string backend_;
  std::unique_ptr<lava::Simulation> sim_;
};

py::dict checkpointDict(const lava::Checkpoint& point) {
  const lava::Comparison& c = point.comparison;
  py::dict d;
  d["step"] = point.step;
  d["equal"] = c.equal;
  d["particles"] = c.particles;
  d["alive"] = c.alive;
  d["max_dx"] = c.maxDx;
  d["max_dv"] = c.maxDv;
  d["max_ulp"] = c.maxUlp;
  return d;
}

// A keyword of render() as the program parses its flag; ValueError naming it.
double numberIn(const py::kwargs& params, const char* name, double fallback, double low,
                double high, bool openLow = false) {
  if (!params.contains(name)) return fallback;
  const py::object given = params[name];
  if (!isNumber(given)) wrongType(name, "a number", given);
  const double value = given.cast<double>();
  if (!(value >= low && value <= high) || (openLow && value == low))
    throw py::value_error(std::string(name) + ": expected " + (openLow ? "(" : "[") +
                          py::repr(py::float_(low)).cast<std::string>() + ", " +
                          py::repr(py::float_(high)).cast<std::string>() + "], got " +
                          py::repr(params[name]).cast<std::string>());
  return value;
}

// A keyword of render() that names a choice; ValueError naming it unless it is a str.
std::string textIn(const py::kwargs& params, const char* name, const std::string& fallback) {
  if (!params.contains(name)) return fallback;
  return textArg(name, params[name]);
}

// size=(width, height) or "WxH", as the program's --size; the device's limit is checked after.
std::vector<int64_t> sizeArg(const py::handle& value) {
  if (py::isinstance<py::str>(value)) {
    const std::string text = value.cast<std::string>();
    const size_t x = text.find('x');
    const auto digits = [](const std::string& t) {
      return !t.empty() && t.size() <= 6 && t.find_first_not_of("0123456789") == std::string::npos;
    };
    if (x == std::string::npos || !digits(text.substr(0, x)) || !digits(text.substr(x + 1)))
      throw py::value_error("size: expected (width, height) or 'WxH', got '" + text + "'");
    return {std::stoll(text.substr(0, x)), std::stoll(text.substr(x + 1))};
  }
  if (isNumber(value) || !py::hasattr(value, "__len__") || py::len(value) != 2)
    wrongType("size", "(width, height) or 'WxH'", value);
  std::vector<int64_t> sides;
  for (const py::handle& side : value) sides.push_back(int64_t(integerArg("size", side, 0, 1u << 20)));
  return sides;
}

// The scene's keys, set from keywords; ValueError naming a bad one.
void setKeys(lava::Scene& scene, const py::kwargs& keys) {
  for (const auto& [key, value] : keys) {
    const std::string name = key.cast<std::string>();
    std::string flag = name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    try {
      lava::setSceneKey(scene, lava::KeyTable::Top, 0, flag,
                        keyText(name, value, keyKind(lava::KeyTable::Top, flag)));
    } catch (const lava::InvalidArgument& e) {
      throw py::value_error(name + ": " + e.detail());
    }
  }
}

// Each RGBA frame as a uint8 (height, width, 3) array, alpha dropped: render()'s result.
py::list rgbFrames(const std::vector<std::vector<uint8_t>>& images, VkExtent2D size) {
  py::list out;
  for (const std::vector<uint8_t>& rgba : images) {
    py::array_t<uint8_t> rgb({py::ssize_t(size.height), py::ssize_t(size.width), py::ssize_t(3)});
    uint8_t* to = rgb.mutable_data();
    for (size_t p = 0; p < size_t(size.width) * size.height; ++p)
      std::memcpy(to + 3 * p, rgba.data() + 4 * p, 3);
    out.append(rgb);
  }
  return out;
}

// lava.Error, its subclasses and lava.ArgumentTypeError; InvalidArgument as ValueError.
void bindErrors(py::module_& m) {
  // Vulkan and resource errors are RuntimeErrors; bad input is a ValueError naming it.
  // Translators are tried newest first: the subclasses after their base.
  const auto error = py::register_exception<lava::Error>(m, "Error", PyExc_RuntimeError);
  error.attr("__doc__") = "Lava's errors other than bad input (that is ValueError).";
  py::register_exception<lava::ResourceError>(m, "ResourceError", error.ptr())
      .attr("__doc__") = "Something ran out or is missing: memory, a device, a file.";
  py::register_exception<lava::VulkanError>(m, "VulkanError", error.ptr())
      .attr("__doc__") = "A Vulkan call failed; the message names it and its VkResult.";
  argumentTypeError = PyErr_NewExceptionWithDoc(
      "lava._lava.ArgumentTypeError",
      "A keyword of the wrong type; its message names it. Both a TypeError and a ValueError.",
      py::make_tuple(py::handle(PyExc_TypeError), py::handle(PyExc_ValueError)).release().ptr(),
      nullptr);
  m.attr("ArgumentTypeError") = py::handle(argumentTypeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lava::InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

// lava.Scene's keys: set(), the counts of its parts, and to_dict().
void bindSceneKeys(py::class_<lava::Scene>& sceneClass) {
  sceneClass
      .def(
          "set",
          [](lava::Scene& scene, const std::string& key, const py::object& value,
             const std::string& table, size_t index) {
            static const std::map<std::string, lava::KeyTable> tables = {
                {"top", lava::KeyTable::Top},
                {"emitter", lava::KeyTable::Emitter},
                {"force", lava::KeyTable::Force},
                {"collider", lava::KeyTable::Collider},
                {"flow", lava::KeyTable::Flow}};
            const auto found = tables.find(table);
            if (found == tables.end())
              throw py::value_error(
                  "table: expected 'top', 'emitter', 'force', 'collider' or 'flow', got '" + table +
                  "'");
            std::string flag = key;
            std::replace(flag.begin(), flag.end(), '_', '-');
            lava::Scene edited = scene;
            try {
              lava::setSceneKey(edited, found->second, index, flag,
                                keyText(key, value, keyKind(found->second, flag)));
              lava::checkScene(edited);
            } catch (const lava::InvalidArgument& e) {
              throw py::value_error(e.what());
            }
            scene = edited;
          },
          py::arg("key"), py::arg("value"), py::arg("table") = "top", py::arg("index") = 0,
          "Sets one key: of the top level (emitter 0's keys included), of table 'emitter',\n"
          "'force' or 'collider' number `index`, or of 'flow'. ValueError names a bad key or\n"
          "value, and the scene stays as it was.")
      .def_property_readonly("particles", &lava::Scene::particles,
                             "Slots of all emitters together.")
      .def_property_readonly(
          "emitters", [](const lava::Scene& s) { return s.emitters.size(); }, "Emitters.")
      .def_property_readonly(
          "forces", [](const lava::Scene& s) { return s.forces.size(); }, "Forces.")
      .def_property_readonly(
          "colliders", [](const lava::Scene& s) { return s.colliders.size(); }, "Colliders.")
      .def(
          "to_dict",
          [](const lava::Scene& scene) {
            return py::module_::import("tomllib").attr("loads")(lava::toToml(scene));
          },
          "The scene as a dict of its TOML: top-level keys, lists of tables under\n"
          "'emitter', 'force' and 'collider', and 'flow' when it has one (a copy: edit\n"
          "with set()).");
}

// lava.Scene's top-level keys as attributes, its TOML as str(), and equality by TOML.
void bindSceneAttributes(py::class_<lava::Scene>& sceneClass) {
  sceneClass
      .def(
          "__getattr__",
          [](const lava::Scene& scene, const std::string& name) -> py::object {
            std::string key = name;
            std::replace(key.begin(), key.end(), '_', '-');
            const py::dict all =
                py::module_::import("tomllib").attr("loads")(lava::toToml(scene));
            if (key != "format" && all.contains(key) && !py::isinstance<py::list>(all[key.c_str()]))
              return all[key.c_str()];
            throw py::attribute_error("lava.Scene has no top-level key '" + name + "'");
          },
          py::arg("name"), "Top-level keys read as attributes: scene.dt, scene.gravity, scene.line_scale.")
      .def(
          "__setattr__",
          [](lava::Scene& scene, const std::string& name, const py::object& value) {
            std::string key = name;
            std::replace(key.begin(), key.end(), '_', '-');
            for (const lava::SceneKey& k : lava::sceneKeys(lava::KeyTable::Top))
              if (k.name == key) {
                lava::Scene edited = scene;
                try {
                  lava::setSceneKey(edited, lava::KeyTable::Top, 0, key,
                                    keyText(name, value, k.kind));
                  lava::checkScene(edited);
                } catch (const lava::InvalidArgument& e) {
                  throw py::value_error(e.what());
                }
                scene = edited;
                return;
              }
            throw py::attribute_error("lava.Scene has no top-level key '" + name + "'");
          },
          py::arg("name"), py::arg("value"), "Top-level keys (emitter 0's included) set as attributes: scene.rate = 4000.")
      .def("__str__", &lava::toToml)
      .def("__repr__",
           [](const lava::Scene& s) {
             return "<lava.Scene: " + std::to_string(s.particles()) + " particles, " +
                    std::to_string(s.emitters.size()) + " emitters, " +
                    std::to_string(s.forces.size()) + " forces, " +
                    std::to_string(s.colliders.size()) + " colliders>";
           })
      .def("__eq__", [](const lava::Scene& a, const lava::Scene& b) {
        return lava::toToml(a) == lava::toToml(b);
      });
}

// lava.Scene: its constructor and TOML text and files, then its keys and attributes.
void bindScene(py::module_& m) {
  py::class_<lava::Scene> sceneClass(
      m, "Scene", R"(A scene: emitters, forces, colliders, integrator and step.

Scene(path=None, **keys) loads a TOML scene file (format 1 or 2) and sets keys given as
keywords, the command line's flags with '-' written '_' (rate=4000, emitter_radius=0.2).
str(scene) is its format-2 TOML; Scene.from_toml(text) reads one back exactly.)");
  sceneClass
      .def(py::init([](const py::object& path, const py::kwargs& keys) {
             lava::Scene scene = options(path, py::kwargs(), {}, {}, "path").scene;
             setKeys(scene, keys);
             lava::checkScene(scene);
             return scene;
           }),
           py::arg("path") = py::none())
      .def_static(
          "from_toml",
          [](const std::string& text, const std::string& name) {
            return lava::parseScene(text, name, [](const std::string& key, const std::string&) {
              return kProgramKeys.count(key) > 0;
            });
          },
          py::arg("text"), py::arg("name") = "<string>",
          "Reads a scene from TOML text; ValueError naming the key for bad input.")
      .def("to_toml", &lava::toToml, "The scene as format-2 TOML text.")
      .def(
          "save",
          [](const lava::Scene& scene, const std::string& path) {
            py::module_::import("pathlib").attr("Path")(path).attr("write_text")(
                lava::toToml(scene));
          },
          py::arg("path"), "Writes the scene to a TOML file that Scene(path) reads back.");
  bindSceneKeys(sceneClass);
  bindSceneAttributes(sceneClass);
}

// lava.simulate(): a run's final state, and optionally its series.
void bindSimulate(py::module_& m) {
  m.def(
      "simulate",
      [](const py::object& steps, const py::object& backend, const py::object& scene,
         const py::object& series, const py::object& every, const py::kwargs& params) {
        const uint64_t n = integerArg("steps", steps, 0, 1000000000);
        const std::string on = textArg("backend", backend);
        const auto sampled = seriesArgs(series, every);
        const Options o = options(scene, params);
        std::unique_ptr<lava::Simulation> sim = make(on, o);
        if (sampled)
          advanceWithSeries(*sim, sampled->first, n, sampled->second);
        else
          advanceInterruptibly(*sim, n);
        lava::State state;
        {
          py::gil_scoped_release release;
          state = sim->state();
        }
        if (on == "gpu") raiseOnValidation(device(o.device));
        return columns(state);
      },
      py::arg("steps"), py::arg("backend") = "gpu", py::arg("scene") = py::none(),
      py::arg("series") = py::none(), py::arg("every") = py::none(),
      "Runs the scene for `steps` steps on the GPU (backend='gpu'), the CPU reference\n"
      "('cpu') or its SIMD twin ('cpu-simd', the same bytes) and returns the final state:\n"
      "float32, shape (particles, 7), columns px py pz vx vy vz age (age -1: not alive),\n"
      "and an 8th, temperature (K), for a scene with a [flow] table.\n"
      "`scene`: a lava.Scene or a TOML scene file; keywords are the command line's flags\n"
      "with '-' written '_' (emitter_radius=0.2), plus device=N and threads=N (CPU). Bad\n"
      "values raise ValueError naming the parameter; Ctrl-C interrupts between batches.\n"
      "series=FOLDER, every=K also write the state every K steps as a VTK time series for\n"
      "ParaView, as `lava simulate --series FOLDER --every K` (FOLDER.pvd beside it).");
}

// lava.validate(): the GPU against the CPU reference, checkpoint by checkpoint.
void bindValidate(py::module_& m) {
  m.def(
      "validate",
      [](const py::object& stepsArg, const py::object& every, const py::object& scene,
         const py::kwargs& params) {
        const uint64_t steps = integerArg("steps", stepsArg, 1, 1000000000);
        const uint64_t k = every.is_none() ? std::max<uint64_t>(1, steps / 10)
                                           : integerArg("every", every, 1, 1000000000);
        const Options o = options(scene, params, {"tolerance_ulp"});
        lava::GpuSimulation gpu(device(o.device), o.scene);
        lava::CpuSimulation cpu(o.scene, std::max(1u, std::thread::hardware_concurrency()));
        lava::ValidationReport report;
        {
          py::gil_scoped_release release;
          report = lava::validate(gpu, cpu, steps, k, o.toleranceUlp.value_or(0));
        }
        raiseOnValidation(device(o.device));
        py::dict out;
        out["passed"] = report.pass;
        out["first_divergent_step"] = report.firstDivergentStep
                                          ? py::object(py::int_(*report.firstDivergentStep))
                                          : py::object(py::none());
        py::list checkpoints;
        for (const lava::Checkpoint& point : report.checkpoints)
          checkpoints.append(checkpointDict(point));
        out["checkpoints"] = checkpoints;
        if (report.firstDifference) {
          const lava::Difference& d = *report.firstDifference;
          py::dict first;
          first["particle"] = d.particle;
          first["emitter"] = d.emitter;
          first["field"] = lava::fieldName(d.field);
          first["gpu_bits"] = d.subjectBits;
          first["cpu_bits"] = d.referenceBits;
          out["first_difference"] = first;
        } else {
          out["first_difference"] = py::none();
        }
        return out;
      },
      py::arg("steps"), py::arg("every") = py::none(), py::arg("scene") = py::none(),
      "Runs the scene on the GPU and on the CPU reference, compares them every `every`\n"
      "steps (default steps/10), and returns {'passed', 'first_divergent_step' (None when\n"
      "bit-exact), 'first_difference', 'checkpoints': [{'step', 'equal', 'particles',\n"
      "'alive', 'max_dx', 'max_dv', 'max_ulp'}]}. tolerance_ulp=U accepts U ULPs.");
}

// lava.render(): frames as `lava render` draws them, as numpy arrays.
void bindRender(py::module_& m) {
  m.def(
      "render",
      [](const py::object& scene, const py::object& framesArg, const py::object& size,
         const py::kwargs& all) {
        static const std::set<std::string> own = {"fps", "warmup", "renderer", "look",
                                                  "exposure", "bloom", "bloom_threshold"};
        const Options o = options(scene, all, {}, own);
        lava::host::FrameRun run;
        run.frames = uint32_t(integerArg("frames", framesArg, 1, 100000));
        const std::vector<int64_t> sides = sizeArg(size);
        lava::Device& d = device(o.device);
        const int64_t limit = d.limits().maxImageDimension2D;
        if (sides.size() != 2 || sides[0] < 1 || sides[1] < 1 || sides[0] > limit ||
            sides[1] > limit)
          throw py::value_error("size: expected (width, height) or 'WxH', each 1 to " +
                                std::to_string(limit) + " on this device, got " +
                                py::repr(size).cast<std::string>());
        run.size = {uint32_t(sides[0]), uint32_t(sides[1])};
        run.fps = numberIn(all, "fps", 30.0, 0.0, 1000.0, true);
        run.warmup = numberIn(all, "warmup", 3.0, 0.0, 600.0);
        run.look.exposure = float(numberIn(all, "exposure", 1.0, 0.0, 16.0, true));
        run.look.bloom = float(numberIn(all, "bloom", 1.0, 0.0, 4.0));
        run.look.threshold = float(numberIn(all, "bloom_threshold", 0.1, 0.0, 16.0));
        const std::string look = textIn(all, "look", "lava");
        if (look != "lava" && look != "plain")
          throw py::value_error("look: expected 'lava' or 'plain', got '" + look + "'");
        run.style = look == "lava" ? lava::LookStyle::Lava : lava::LookStyle::Plain;
        const std::string lines =
            textIn(all, "renderer", o.scene.particles() >= lava::kSplatFrom ? "splat" : "lines");
        if (lines != "lines" && lines != "splat")
          throw py::value_error("renderer: expected 'lines' or 'splat', got '" + lines + "'");
        run.lines = lines == "splat" ? lava::LineMode::Splat : lava::LineMode::Lines;
        std::vector<std::vector<uint8_t>> images;
        {
          py::gil_scoped_release release;
          lava::host::renderFrames(d, o.scene, run, [&](uint32_t, const std::vector<uint8_t>& rgba) {
            images.push_back(rgba);
            py::gil_scoped_acquire acquire;
            checkSignals();
          });
        }
        raiseOnValidation(d);
        return rgbFrames(images, run.size);
      },
      py::arg("scene") = py::none(), py::arg("frames") = 1,
      py::arg("size") = py::make_tuple(1280, 720),
      "Renders `frames` frames of the scene, as `lava render` does, and returns them as a\n"
      "list of uint8 arrays of shape (height, width, 3), equal pixel for pixel to its PNGs\n"
      "with the same arguments. size=(width, height) or 'WxH'; keywords: fps (30), warmup (3 s),\n"
      "renderer ('lines' or 'splat'; splat from 16384 particles), look ('lava' or\n"
      "'plain'), exposure, bloom, bloom_threshold, device, and the scene's keys.");
}

// lava.Simulation's read-only properties: its particles, step, backend and scene.
void bindSimulationProperties(py::class_<Simulation>& simulationClass) {
  simulationClass
      .def_property_readonly(
          "particles",
          [](py::object self) {
            Simulation& s = self.cast<Simulation&>();
            if (lava::CpuSimulation* cpu = s.cpu()) {
              // The CPU backend's memory itself: no copy, alive as long as the Simulation.
              const std::vector<lava::Particle>& p = cpu->view().particles;
              py::array_t<float> view({py::ssize_t(p.size()), py::ssize_t(8)},
                                      {py::ssize_t(sizeof(lava::Particle)), py::ssize_t(4)},
                                      &p.front().px, self);
              view.attr("flags").attr("writeable") = false;
              return view;
            }
            const std::vector<lava::Particle> p = s.simulation().state().particles;
            py::array_t<float> out({py::ssize_t(p.size()), py::ssize_t(8)});
            std::memcpy(out.mutable_data(), p.data(), p.size() * sizeof(lava::Particle));
            return out;
          },
          "Raw slots, float32 (particles, 8): px py pz age vx vy vz mass. For the CPU backend\n"
          "a read-only view of its memory (no copy, updated by advance()); for the GPU a\n"
          "read-back copy.")
      .def_property_readonly("step", &Simulation::step, "Steps taken since the start.")
      .def_property_readonly("backend", &Simulation::backend,
                             "'gpu', 'cpu' or 'cpu-simd'.")
      .def_property_readonly(
          "scene", [](const Simulation& s) { return s.scene(); },
          "The running scene (a copy): a lava.Scene.")
      .def_property_readonly(
          "scene_toml", [](const Simulation& s) { return lava::toToml(s.scene()); },
          "The scene as a format-2 TOML text (save it, load it with scene=...).");
}

// lava.Simulation: made, resumed, advanced, read, written and checkpointed.
void bindSimulation(py::module_& m) {
  py::class_<Simulation> simulationClass(
      m, "Simulation",
      "A simulation to advance step by step: Simulation(scene=None,\n"
      "backend='gpu', **keys), `scene` a lava.Scene or a TOML path, the\n"
      "keywords those of simulate().");
  simulationClass
      .def(py::init<const py::object&, const py::object&, const py::kwargs&>(),
           py::arg("scene") = py::none(), py::arg("backend") = "gpu")
      .def_static(
          "resume",
          [](const py::object& pathArg_, const py::object& backendArg, const py::kwargs& params) {
            const std::string path = pathArg("path", pathArg_);
            const std::string backend = textArg("backend", backendArg);
            for (const auto& [key, value] : params) {
              const std::string name = key.cast<std::string>();
              if (name != "device" && name != "threads")
                throw py::value_error(name + ": resume() takes device and threads; the scene "
                                             "is the checkpoint's");
            }
            Options o = options(py::none(), params, {}, {});
            const lava::Snapshot snapshot = lava::readCheckpoint(path);
            o.scene = snapshot.scene;
            auto sim = std::make_unique<Simulation>(std::move(o), backend);
            sim->simulation().setState(snapshot.state);
            return sim;
          },
          py::arg("path"), py::arg("backend") = "gpu",
          "A simulation from a checkpoint file (checkpoint() or `lava simulate --checkpoint`),\n"
          "on any backend: it goes on bit for bit. Keywords: device, threads.")
      .def("advance", &Simulation::advance, py::arg("steps"),
           "Runs `steps` steps (Ctrl-C interrupts between batches, at a whole step).")
      .def("write_series", &Simulation::writeSeries, py::arg("folder"), py::arg("steps"),
           py::arg("every"),
           "Runs `steps` steps writing the state every `every` steps as a VTK time series\n"
           "for ParaView, as `lava simulate --series folder --every K`: folder/step_*.vtp and\n"
           "folder.pvd beside it. From step 0 a new series; from a later step (a resumed\n"
           "simulation, or one advanced before) the series in `folder` continued.")
      .def("state", &Simulation::state,
           "The state as simulate() returns it (a copy): float32 (particles, 7).")
      .def("set_state", &Simulation::setState, py::arg("particles"),
           "Replaces the slots with float32 (particles, 8) as `particles` gives them; the\n"
           "step and the emitters' clocks stay.")
      .def("checkpoint", &Simulation::checkpoint, py::arg("path"),
           "Writes the scene and the whole state to a checkpoint file (atomically), which\n"
           "Simulation.resume() and `lava simulate --resume` continue bit for bit.");
  bindSimulationProperties(simulationClass);
}

}  // namespace

PYBIND11_MODULE(_lava, m) {
  m.doc() = "Lava: a Vulkan compute-shader particle engine, bit-exact on GPU and CPU";
  m.attr("__version__") = lava::versionString();
  bindErrors(m);
  bindScene(m);
  bindSimulate(m);
  bindValidate(m);
  bindRender(m);
  bindSimulation(m);
}
