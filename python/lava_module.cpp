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
                std::set<std::string> extra = {}) {
  Options o;
  if (!scenePath.is_none()) {
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

// Particles as the .npy columns: px py pz vx vy vz age (-1: not alive).
py::array_t<float> columns(const std::vector<lava::Particle>& particles) {
  py::array_t<float> out({py::ssize_t(particles.size()), py::ssize_t(7)});
  auto rows = out.mutable_unchecked<2>();
  for (size_t i = 0; i < particles.size(); ++i) {
    const lava::Particle& p = particles[i];
    const float row[7] = {p.px, p.py, p.pz, p.vx, p.vy, p.vz, p.age < 0.0f ? -1.0f : p.age};
    for (int c = 0; c < 7; ++c) rows(py::ssize_t(i), c) = row[c];
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

// A running simulation for scripts: advance it, look at it.
class Simulation {
 public:
  Simulation(const std::string& backend, const py::object& scene, const py::kwargs& params)
      : options_(options(scene, params)), backend_(backend), sim_(make(backend, options_)) {}

  void advance(uint64_t steps) {
    {
      py::gil_scoped_release release;
      sim_->advance(steps);
    }
    if (backend_ == "gpu") raiseOnValidation(device(options_.device));
  }
  py::array_t<float> state() { return columns(sim_->state().particles); }
  uint64_t step() {
    if (auto* cpu = dynamic_cast<lava::CpuSimulation*>(sim_.get())) return cpu->view().step;
    return static_cast<lava::GpuSimulation*>(sim_.get())->step();
  }
  const lava::Scene& scene() const { return sim_->scene(); }
  lava::CpuSimulation* cpu() { return dynamic_cast<lava::CpuSimulation*>(sim_.get()); }
  lava::Simulation& simulation() { return *sim_; }
  const std::string& backend() const { return backend_; }

 private:
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

}  // namespace

PYBIND11_MODULE(_lava, m) {
  m.doc() = "Lava: a Vulkan compute-shader particle engine, bit-exact on GPU and CPU";
  m.attr("__version__") = lava::versionString();
  py::register_exception<lava::ResourceError>(m, "ResourceError", PyExc_RuntimeError);
  py::register_exception<lava::VulkanError>(m, "VulkanError", PyExc_RuntimeError);

  m.def(
      "simulate",
      [](uint64_t steps, const std::string& backend, const py::object& scene,
         const py::kwargs& params) {
        const Options o = options(scene, params);
        std::unique_ptr<lava::Simulation> sim = make(backend, o);
        std::vector<lava::Particle> particles;
        {
          py::gil_scoped_release release;
          sim->advance(steps);
          particles = sim->state().particles;
        }
        if (backend == "gpu") raiseOnValidation(device(o.device));
        return columns(particles);
      },
      py::arg("steps"), py::arg("backend") = "gpu", py::arg("scene") = py::none(),
      "Runs the scene for `steps` steps on the GPU (backend='gpu'), the CPU reference\n"
      "('cpu') or its SIMD twin ('cpu-simd', the same bytes) and returns the final state:\n"
      "float32, shape (particles, 7), columns\n"
      "px py pz vx vy vz age (age -1: not alive). `scene`: a TOML scene file; keywords are\n"
      "the command line's flags with '-' written '_' (emitter_radius=0.2), plus device=N\n"
      "and threads=N (CPU). Bad values raise ValueError naming the parameter.");

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

  py::class_<Simulation>(m, "Simulation",
                         "A simulation to advance step by step: Simulation(backend='gpu',\n"
                         "scene=None, **params) with the keywords of simulate().")
      .def(py::init<const std::string&, const py::object&, const py::kwargs&>(),
           py::arg("backend") = "gpu", py::arg("scene") = py::none())
      .def("advance", &Simulation::advance, py::arg("steps"), "Runs `steps` steps.")
      .def("state", &Simulation::state,
           "The state as simulate() returns it (a copy): float32 (particles, 7).")
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
      .def_property_readonly("backend", &Simulation::backend)
      .def_property_readonly(
          "scene_toml", [](const Simulation& s) { return lava::toToml(s.scene()); },
          "The scene as a format-2 TOML text (save it, load it with scene=...).");
}
