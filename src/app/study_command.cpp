// `lava study`: the handout's lesson on integrators as a table. One particle of the scene's
// emitter 0 (spread and radius 0), gravity only, on the CPU reference: per integrator and
// step size, the largest position error against the closed form x0 + v0 t - g t^2 / 2 y
// before the first ground contact, and the energy E(T) / E(0) after T seconds with an
// elastic ground (restitution = friction = 1).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "commands.h"
#include "flow_study.h"
#include "host/output.h"
#include "lava/lava.h"
#include "lava/scene_keys.h"
#include "options.h"
#include "paths.h"
#include "runtime.h"

namespace lava::app {
namespace {

struct Run {
  Integrator integrator;
  double dt;
  uint64_t steps;
  double maxError;                                // m, before the first ground contact
  double energyRatio;                             // E(T) / E(0)
  std::vector<std::pair<double, double>> energy;  // (t, E / E0) samples
};

double energyOf(const Particle& p, double g) {
  const double v2 = double(p.vx) * p.vx + double(p.vy) * p.vy + double(p.vz) * p.vz;
  return p.mass * (0.5 * v2 + g * p.py);
}

class StudyCommand final : public Command {
 public:
  explicit StudyCommand(CLI::App& app)
      : Command(app, "study", "integrator accuracy and energy for one particle"),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
    addTableFlags();
    addFlowFlags();
    addOutputFlags();
  }

  int run() override {
    options_.resolve();
    if (!flow_.empty()) return runFlow();
    const Emitter& e = scene_.emitters.at(0);
    std::printf(
        "study: one particle from (%g, %g, %g) m at (%g, %g, %g) m/s, g = %g m/s^2, "
        "%g s, elastic ground; drag, wind, forces and colliders left out\n",
        double(e.position.x), double(e.position.y), double(e.position.z), double(e.velocity.x),
        double(e.velocity.y), double(e.velocity.z), double(scene_.gravity), seconds_);
    std::printf("%-20s %9s %9s %18s %12s\n", "integrator", "dt (s)", "steps", "max |x - x*| (m)",
                "E(T)/E(0)");
    std::string table = "integrator,dt,steps,max_position_error,energy_ratio\n";
    std::string series = "integrator,dt,t,energy_ratio\n";
    for (Integrator integrator : integrators_)
      for (double dt : dts_) {
        const Run r = study(integrator, dt);
        std::printf("%-20s %9g %9llu %18.6g %12.6f\n", name(integrator), dt,
                    static_cast<unsigned long long>(r.steps), r.maxError, r.energyRatio);
        char row[160];
        std::snprintf(row, sizeof(row), "%s,%.9g,%llu,%.9g,%.9g\n", name(integrator), dt,
                      static_cast<unsigned long long>(r.steps), r.maxError, r.energyRatio);
        table += row;
        for (const auto& [t, ratio] : r.energy) {
          std::snprintf(row, sizeof(row), "%s,%.9g,%.9g,%.9g\n", name(integrator), dt, t, ratio);
          series += row;
        }
      }
    if (!csv_.empty()) host::writeFileAtomically(csv_, table);
    if (!energyCsv_.empty()) host::writeFileAtomically(energyCsv_, series);
    return 0;
  }

 private:
  // --integrators, --dts and --seconds: the table's runs (--flow reads the last two too).
  void addTableFlags() {
    options_.add("integrators",
                 "comma-separated subset of explicit-euler,semi-implicit-euler,velocity-verlet "
                 "[all three]",
                 [this](const std::string& src, const std::string& t) {
                   integrators_.clear();
                   for (const std::string& name : split(src, t)) {
                     Scene probe;
                     try {
                       setSceneKey(probe, KeyTable::Top, 0, "integrator", name);
                     } catch (const InvalidArgument& e) {
                       throw UsageError(src + ": " + e.detail());
                     }
                     integrators_.push_back(probe.integrator);
                   }
                 });
    options_.add("dts", "comma-separated step sizes in s, each 1e-5..0.1 [0.0001,...,0.03]",
                 [this](const std::string& src, const std::string& t) {
                   dts_.clear();
                   for (const std::string& item : split(src, t))
                     dts_.push_back(parseNumber(src, item, 1e-5, 0.1));
                 });
    options_.add("seconds", "simulated time T for the energy ratio, (0, 1000] [10]",
                 [this](const std::string& src, const std::string& t) {
                   seconds_ = parseNumber(src, t, 0.0, 1000.0, true);
                 });
  }

  // --flow and the flags only it reads (--viscosity, --solver).
  void addFlowFlags() {
    options_.add(
        "flow",
        "instead: the flow against a published solution, on the CPU reference; one of " +
            std::string(kFlowCases) + " (docs/flow.md); exit 1 outside its tolerance",
        [this](const std::string& src, const std::string& t) {
          const std::string cases = std::string(", ") + kFlowCases + ",";
          if (t.empty() || cases.find(", " + t + ",") == std::string::npos)
            throw UsageError(src + ": expected one of " + kFlowCases + ", got '" + t + "'");
          flow_ = t;
        });
    options_.add("viscosity",
                 "--flow: the flow's constant viscosity (m^2/s), [1e-6, 1e4] [the case's]",
                 [this](const std::string& src, const std::string& t) {
                   viscosity_ = parseNumber(src, t, 1e-6, 1e4);
                 });
    options_.add("solver", "--flow: the flow's method, explicit or implicit [implicit]",
                 [this](const std::string& src, const std::string& t) {
                   if (t == "explicit")
                     solver_ = FlowSolver::Explicit;
                   else if (t == "implicit")
                     solver_ = FlowSolver::Implicit;
                   else
                     throw UsageError(src + ": expected explicit or implicit, got '" + t + "'");
                 });
  }

  // --csv and --energy-csv: the files the results also go to.
  void addOutputFlags() {
    options_.add("csv", "also write the table to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   csv_ = t;
                 });
    options_.add("energy-csv", "also write E(t)/E(0) over time, every run, to FILE.csv",
                 [this](const std::string& src, const std::string& t) {
                   checkOutputPath(src, t, ".csv");
                   energyCsv_ = t;
                 });
  }

  static std::vector<std::string> split(const std::string& source, const std::string& text) {
    std::vector<std::string> items;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');) items.push_back(item);
    if (items.empty() || text.back() == ',')
      throw UsageError(source + ": expected a comma-separated list, got '" + text + "'");
    return items;
  }

  // Each step size of --dts (default 1 ms and 1/120 s): the case's samples and verdict.
  int runFlow() const {
    const std::vector<double> dts =
        options_.given("dts") ? dts_ : std::vector<double>{0.001, 1.0 / 120.0};
    std::string table = "case,dt,viscosity,t,measured,published\n";
    bool holds = true;
    for (double dt : dts) {
      FlowStudyOptions o;
      o.name = flow_;
      o.viscosity = viscosity_;
      o.solver = solver_;
      o.dt = dt;
      o.seconds = options_.given("seconds") ? seconds_ : 0.0;
      const FlowStudy study = studyFlow(o);
      std::printf("study --flow %s, dt = %g s%s: %s against %s\n", flow_.c_str(), dt,
                  viscosity_ > 0.0 ? (", viscosity " + std::to_string(viscosity_)).c_str() : "",
                  study.quantity.c_str(), study.reference.c_str());
      std::printf("%10s %14s %14s %9s\n", "t (s)", "measured", "published", "ratio");
      for (const FlowSample& x : study.samples) {
        std::printf("%10.4f %14.6g %14.6g %9.3f\n", x.t, x.measured, x.published,
                    x.published != 0.0 ? x.measured / x.published : 0.0);
        char row[200];
        std::snprintf(row, sizeof(row), "%s,%.9g,%.9g,%.9g,%.9g,%.9g\n", flow_.c_str(), dt,
                      viscosity_, x.t, x.measured, x.published);
        table += row;
      }
      std::printf("%s: deviation %.3g, tolerance %.3g\n", study.holds() ? "holds" : "FAILS",
                  study.deviation, study.tolerance);
      holds = holds && study.holds();
    }
    if (!csv_.empty()) host::writeFileAtomically(csv_, table);
    return holds ? 0 : 1;
  }

  Run study(Integrator integrator, double dt) const {
    Scene s = scene_;
    s.integrator = integrator;
    s.dt = dt;
    s.restitution = 1.0f;
    s.friction = 1.0f;
    s.drag = 0.0f;
    s.wind = {};
    s.forces.clear();
    s.colliders.clear();
    s.emitters.resize(1);
    Emitter& e = s.emitters[0];
    e.particles = 1;
    e.rate = 0.0;
    e.burst = 1;  // born in step 0
    e.burstInterval = 0.0;
    e.spread = {};
    e.radius = 0.0f;
    e.lifetime = 0.0f;
    CpuSimulation sim(s);
    Run r{integrator, dt, s.stepsIn(seconds_), 0.0, 1.0, {}};
    const double g = s.gravity, h = s.h();
    const Vec3 x0 = e.position, v0 = e.velocity;
    const double e0 =
        e.mass *
        (0.5 * (double(v0.x) * v0.x + double(v0.y) * v0.y + double(v0.z) * v0.z) + g * x0.y);
    const uint64_t sampleEvery = std::max<uint64_t>(1, r.steps / 400);
    bool flying = true;
    for (uint64_t k = 1; k <= r.steps; ++k) {
      sim.advance(1);
      const Particle& p = sim.view().particles[0];
      const double t = double(k) * h;
      const double exact[3] = {x0.x + v0.x * t, x0.y + v0.y * t - 0.5 * g * t * t, x0.z + v0.z * t};
      flying = flying && exact[1] > 0.0 && p.py > 0.0f;
      if (flying) {
        const double dx = p.px - exact[0], dy = p.py - exact[1], dz = p.pz - exact[2];
        r.maxError = std::max(r.maxError, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
      if (k % sampleEvery == 0 || k == r.steps) r.energy.emplace_back(t, energyOf(p, g) / e0);
    }
    r.energyRatio = r.energy.empty() ? 1.0 : r.energy.back().second;
    return r;
  }

  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
  std::vector<Integrator> integrators_{Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                       Integrator::VelocityVerlet};
  std::vector<double> dts_{0.0001, 0.0003, 0.001, 0.003, 0.01, 0.03};
  double seconds_ = 10.0;
  std::string csv_;
  std::string energyCsv_;
  std::string flow_;        // --flow: a published solution's case
  double viscosity_ = 0.0;  // --flow's viscosity; 0: the case's
  FlowSolver solver_ = FlowSolver::Implicit;
};

}  // namespace

std::unique_ptr<Command> makeStudy(CLI::App& app) {
  return std::make_unique<StudyCommand>(app);
}

}  // namespace lava::app
