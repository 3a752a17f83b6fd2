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

// A Python value as the text scene keys read.
std::string keyText(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value))
    throw py::value_error(name + ": expected a number or a name, got a bool");
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  if (py::isinstance<py::sequence>(value) || py::hasattr(value, "__len__")) {
    std::string joined;
    for (const py::handle& item : value) {
      const py::object number = py::reinterpret_borrow<py::object>(item);
      const py::object asFloat = py::float_(number);
      joined += (joined.empty() ? "" : ",") + py::repr(asFloat).cast<std::string>();
    }
    return joined;
  }
  throw py::value_error(name + ": expected a number, a name or a sequence of 3 numbers");
}

struct Options {
  lava::Scene scene;
  std::optional<unsigned> device;
  unsigned threads = 1;
  std::optional<uint32_t> toleranceUlp;
};

// The scene file (if any), then each keyword: scene keys, device, threads, tolerance_ulp.
Options options(const py::object& scenePath, const py::kwargs& params,
                std::set<std::string> extra = {}, std::set<std::string> skip = {}) {
  Options o;
  if (py::isinstance<lava::Scene>(scenePath)) {
    o.scene = scenePath.cast<lava::Scene>();
  } else if (!scenePath.is_none()) {
    const std::string path = py::str(scenePath).cast<std::string>();
    try {
      o.scene = lava::loadScene(path, [](const std::string& key, const std::string&) {
        return kProgramKeys.count(key) > 0;
      });
    } catch (const lava::InvalidArgument& e) {
      throw py::value_error(std::string("scene: ") + e.what());
    }
  }
  for (const auto& [key, value] : params) {
    const std::string name = key.cast<std::string>();
    if (skip.count(name)) continue;  // the caller's own keywords
    std::string flag = name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (name == "device") {
      o.device = value.cast<unsigned>();
    } else if (name == "threads") {
      const int threads = value.cast<int>();
      if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0 to 1024");
      o.threads = threads ? unsigned(threads) : std::max(1u, std::thread::hardware_concurrency());
    } else if (name == "tolerance_ulp" && extra.count(name)) {
      o.toleranceUlp = value.cast<uint32_t>();
    } else {
      try {
        lava::setSceneKey(o.scene, lava::KeyTable::Top, 0, flag, keyText(name, value));
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

// A running simulation for scripts: advance it, look at it, save and resume it.
class Simulation {
 public:
  Simulation(const py::object& scene, const std::string& backend, const py::kwargs& params)
      : options_(options(scene, params)), backend_(backend), sim_(make(backend, options_)) {}
  Simulation(Options o, const std::string& backend)
      : options_(std::move(o)), backend_(backend), sim_(make(backend, options_)) {}

  void advance(uint64_t steps) {
    advanceInterruptibly(*sim_, steps);
    validated();
  }
  py::array_t<float> state() {
    const lava::State state = sim_->state();
    validated();
    return columns(state);
  }
  // Raw slots (particles, 8), as `particles` gives them; step and clocks stay.
  void setState(const py::array_t<float, py::array::c_style | py::array::forcecast>& raw) {
    lava::State state = sim_->state();
    if (raw.ndim() != 2 || raw.shape(1) != 8 || size_t(raw.shape(0)) != state.particles.size())
      throw py::value_error("particles: expected float32 (" +
                            std::to_string(state.particles.size()) + ", 8), as `particles` is");
    std::memcpy(state.particles.data(), raw.data(), state.particles.size() * sizeof(lava::Particle));
    sim_->setState(state);
    validated();
  }
  void checkpoint(const std::string& path) {
    const lava::State state = sim_->state();
    lava::writeCheckpoint(path, sim_->scene(), state);
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
  if (py::isinstance<py::bool_>(given) ||
      !(py::isinstance<py::int_>(given) || py::isinstance<py::float_>(given)))
    throw py::value_error(std::string(name) + ": expected a number, got " +
                          py::repr(given).cast<std::string>());
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
  if (!py::isinstance<py::str>(params[name]))
    throw py::value_error(std::string(name) + ": expected a str, got " +
                          py::repr(params[name]).cast<std::string>());
  return params[name].cast<std::string>();
}

// The scene's keys, set from keywords; ValueError naming a bad one.
void setKeys(lava::Scene& scene, const py::kwargs& keys) {
  for (const auto& [key, value] : keys) {
    const std::string name = key.cast<std::string>();
    std::string flag = name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    try {
      lava::setSceneKey(scene, lava::KeyTable::Top, 0, flag, keyText(name, value));
    } catch (const lava::InvalidArgument& e) {
      throw py::value_error(name + ": " + e.detail());
    }
  }
}

}  // namespace

PYBIND11_MODULE(_lava, m) {
  m.doc() = "Lava: a Vulkan compute-shader particle engine, bit-exact on GPU and CPU";
  m.attr("__version__") = lava::versionString();
  // Vulkan and resource errors are RuntimeErrors; bad input is a ValueError naming it.
  // Translators are tried newest first: the subclasses after their base.
  const auto error = py::register_exception<lava::Error>(m, "Error", PyExc_RuntimeError);
  error.attr("__doc__") = "Lava's errors other than bad input (that is ValueError).";
  py::register_exception<lava::ResourceError>(m, "ResourceError", error.ptr())
      .attr("__doc__") = "Something ran out or is missing: memory, a device, a file.";
  py::register_exception<lava::VulkanError>(m, "VulkanError", error.ptr())
      .attr("__doc__") = "A Vulkan call failed; the message names it and its VkResult.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lava::InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<lava::Scene>(m, "Scene", R"(A scene: emitters, forces, colliders, integrator and step.

Scene(path=None, **keys) loads a TOML scene file (format 1 or 2) and sets keys given as
keywords, the command line's flags with '-' written '_' (rate=4000, emitter_radius=0.2).
str(scene) is its format-2 TOML; Scene.from_toml(text) reads one back exactly.)")
      .def(py::init([](const py::object& path, const py::kwargs& keys) {
             lava::Scene scene = options(path, py::kwargs()).scene;
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
          py::arg("path"), "Writes the scene to a TOML file that Scene(path) reads back.")
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
              lava::setSceneKey(edited, found->second, index, flag, keyText(key, value));
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
          "with set()).")
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
                  lava::setSceneKey(edited, lava::KeyTable::Top, 0, key, keyText(name, value));
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

  m.def(
      "simulate",
      [](uint64_t steps, const std::string& backend, const py::object& scene,
         const py::kwargs& params) {
        const Options o = options(scene, params);
        std::unique_ptr<lava::Simulation> sim = make(backend, o);
        advanceInterruptibly(*sim, steps);
        lava::State state;
        {
          py::gil_scoped_release release;
          state = sim->state();
        }
        if (backend == "gpu") raiseOnValidation(device(o.device));
        return columns(state);
      },
      py::arg("steps"), py::arg("backend") = "gpu", py::arg("scene") = py::none(),
      "Runs the scene for `steps` steps on the GPU (backend='gpu'), the CPU reference\n"
      "('cpu') or its SIMD twin ('cpu-simd', the same bytes) and returns the final state:\n"
      "float32, shape (particles, 7), columns px py pz vx vy vz age (age -1: not alive),\n"
      "and an 8th, temperature (K), for a scene with a [flow] table.\n"
      "`scene`: a lava.Scene or a TOML scene file; keywords are the command line's flags\n"
      "with '-' written '_' (emitter_radius=0.2), plus device=N and threads=N (CPU). Bad\n"
      "values raise ValueError naming the parameter; Ctrl-C interrupts between batches.");

  m.def(
      "validate",
      [](uint64_t steps, const py::object& every, const py::object& scene,
         const py::kwargs& params) {
        const Options o = options(scene, params, {"tolerance_ulp"});
        if (steps == 0) throw py::value_error("steps: expected at least 1");
        const uint64_t k =
            every.is_none() ? std::max<uint64_t>(1, steps / 10) : every.cast<uint64_t>();
        if (k == 0) throw py::value_error("every: expected at least 1");
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

  m.def(
      "render",
      [](const py::object& scene, uint32_t frames, const py::object& size, const py::kwargs& all) {
        static const std::set<std::string> own = {"fps", "warmup", "renderer", "look",
                                                  "exposure", "bloom", "bloom_threshold"};
        const Options o = options(scene, all, {}, own);
        if (frames < 1 || frames > 100000)
          throw py::value_error("frames: expected 1 to 100000, got " + std::to_string(frames));
        lava::host::FrameRun run;
        run.frames = frames;
        const auto sides = size.cast<std::vector<int64_t>>();
        lava::Device& d = device(o.device);
        const int64_t limit = d.limits().maxImageDimension2D;
        if (sides.size() != 2 || sides[0] < 1 || sides[1] < 1 || sides[0] > limit ||
            sides[1] > limit)
          throw py::value_error("size: expected (width, height), each 1 to " +
                                std::to_string(limit) + " on this device");
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
        py::list out;
        for (const std::vector<uint8_t>& rgba : images) {
          py::array_t<uint8_t> rgb({py::ssize_t(run.size.height), py::ssize_t(run.size.width),
                                    py::ssize_t(3)});
          uint8_t* to = rgb.mutable_data();
          for (size_t p = 0; p < size_t(run.size.width) * run.size.height; ++p)
            std::memcpy(to + 3 * p, rgba.data() + 4 * p, 3);
          out.append(rgb);
        }
        return out;
      },
      py::arg("scene") = py::none(), py::arg("frames") = 1,
      py::arg("size") = py::make_tuple(1280, 720),
      "Renders `frames` frames of the scene, as `lava render` does, and returns them as a\n"
      "list of uint8 arrays of shape (height, width, 3), equal pixel for pixel to its PNGs\n"
      "with the same arguments. size=(width, height); keywords: fps (30), warmup (3 s),\n"
      "renderer ('lines' or 'splat'; splat from 16384 particles), look ('lava' or\n"
      "'plain'), exposure, bloom, bloom_threshold, device, and the scene's keys.");

  py::class_<Simulation>(m, "Simulation",
                         "A simulation to advance step by step: Simulation(scene=None,\n"
                         "backend='gpu', **keys), `scene` a lava.Scene or a TOML path, the\n"
                         "keywords those of simulate().")
      .def(py::init<const py::object&, const std::string&, const py::kwargs&>(),
           py::arg("scene") = py::none(), py::arg("backend") = "gpu")
      .def_static(
          "resume",
          [](const std::string& path, const std::string& backend, const py::kwargs& params) {
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
      .def("state", &Simulation::state,
           "The state as simulate() returns it (a copy): float32 (particles, 7).")
      .def("set_state", &Simulation::setState, py::arg("particles"),
           "Replaces the slots with float32 (particles, 8) as `particles` gives them; the\n"
           "step and the emitters' clocks stay.")
      .def("checkpoint", &Simulation::checkpoint, py::arg("path"),
           "Writes the scene and the whole state to a checkpoint file (atomically), which\n"
           "Simulation.resume() and `lava simulate --resume` continue bit for bit.")
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
