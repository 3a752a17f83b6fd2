// The flow against published solutions (docs/flow.md, "Against published solutions"). Each
// case is a scene of flow particles filled on the lattice at rest, with constant viscosity
// and no cooling, run on the CPU reference; gravity is tilted for a slope (gravity g cos θ
// along -y, a wind of m g sin θ along +x), so the ground is the slope.
#include "flow_study.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "lava/simulation.h"

namespace lava::app {

const char* const kFlowCases = "nusselt, dam-break, huppert-slope, huppert-spread, at-rest";

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

// Martin & Moyce (1952), n^2 = 2: T = t sqrt(2g/a), Z = front / a
// (docs/data/martin-moyce-1952.csv).
constexpr double kMartinMoyce[][2] = {{0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67},
                                      {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56},
                                      {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22}, {2.83, 3.44},
                                      {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11}};

// A flow of constant viscosity `nu`, never cooling, and one emitter filling a box of
// n.x by n.y by n.z lattice sites of `spacing` centred at `centre`, at rest.
Scene latticeScene(double nu, double dt, float spacing, float radius, float density,
                   const Vec3& centre, const Vec3& sites) {
  Scene s;
  s.dt = dt;
  s.flow.emplace();
  Flow& f = *s.flow;
  f.radius = radius;
  f.density = density;
  f.viscosity = f.viscositySolidus = float(nu);
  f.coolingAir = f.coolingGround = 0.0f;
  Emitter& e = s.emitters.at(0);
  e.flow = true;
  e.fill = Fill::Lattice;
  e.shape = Shape::Box;
  e.rate = 0.0;
  e.mass = float(double(density) * spacing * spacing * spacing);
  e.position = centre;
  e.size = {0.5f * spacing * sites.x, 0.5f * spacing * sites.y, 0.5f * spacing * sites.z};
  e.velocity = e.spread = {};
  e.particles = e.burst = uint32_t(sites.x * sites.y * sites.z);
  return s;
}

// Gravity tilted by `degrees`: the ground is a slope falling towards +x.
void tilt(Scene& s, double degrees) {
  const double theta = degrees * kPi / 180.0;
  s.gravity = float(kG * std::cos(theta));
  s.wind = {float(double(s.emitters[0].mass) * kG * std::sin(theta)), 0.0f, 0.0f};
}

// A free-slip plane wall through `at`, facing `normal`.
void wall(Scene& s, const Vec3& at, const Vec3& normal) {
  Collider c;
  c.type = ColliderType::Plane;
  c.position = at;
  c.normal = normal;
  c.restitution = 0.0f;
  c.friction = 1.0f;
  s.colliders.push_back(c);
}

// Side walls at z = +-half: a 2-D flow in x and y.
void sides(Scene& s, float half) {
  wall(s, {0.0f, 0.0f, -half}, {0.0f, 0.0f, 1.0f});
  wall(s, {0.0f, 0.0f, half}, {0.0f, 0.0f, -1.0f});
}

// Runs `s` to each time of `times` (ascending), calling look(t, state) there.
void run(Scene s, const FlowStudyOptions& o, const std::vector<double>& times,
         const std::function<void(double, const State&)>& look) {
  s.flow->solver = o.solver;
  CpuSimulation sim(s, o.threads);
  uint64_t done = 0;
  for (double t : times) {
    const uint64_t step = s.stepsIn(t);
    sim.advance(step - std::min(step, done));
    done = std::max(done, step);
    look(double(done) * double(s.h()), sim.view());
  }
}

// The farthest particle along x: a current's front.
double front(const State& state) {
  float x = 0.0f;
  for (const Particle& p : state.particles) x = std::max(x, p.px);
  return x;
}

std::vector<double> every(double dt, double until) {
  std::vector<double> times;
  for (int k = 1; double(k) * dt <= until * (1.0 + 1e-9); ++k) times.push_back(double(k) * dt);
  return times;
}

// The largest |measured / published - 1| over the samples from `from` seconds on.
double deviation(const std::vector<FlowSample>& samples, double from) {
  double worst = 0.0;
  for (const FlowSample& s : samples)
    if (s.t >= from - 1e-9) worst = std::max(worst, std::fabs(s.measured / s.published - 1.0));
  return worst;
}

// A long film on a 30° slope with a no-slip ground: its middle third's depth-averaged speed
// against Nusselt's g sin θ H^2 / (3ν), H the middle's depth from its particles' volume.
FlowStudy nusselt(const FlowStudyOptions& o) {
  const double nu = o.viscosity > 0.0 ? o.viscosity : 1.0;
  constexpr float kSpacing = 0.03f, kWidth = 4.0f * kSpacing;
  Scene s = latticeScene(nu, o.dt, kSpacing, 2.0f * kSpacing, 2600.0f, {0.0f, 0.09f, 0.0f},
                         {100.0f, 6.0f, 4.0f});
  tilt(s, 30.0);
  s.friction = 0.0f;
  sides(s, 0.5f * kWidth);
  const double volume = double(s.emitters[0].mass) / 2600.0;
  const double depth = 6.0 * kSpacing;
  const double seconds =
      o.seconds > 0.0 ? o.seconds : std::min(4.0, std::max(1.0, 5.0 * depth * depth / nu));
  FlowStudy study{"depth-averaged speed (m/s)", "Nusselt: g sin(30°) H^2 / (3 nu)", {}, 0.0, 0.2};
  run(s, o, every(seconds / 20.0, seconds), [&](double t, const State& state) {
    std::vector<float> xs;
    for (const Particle& p : state.particles) xs.push_back(p.px);
    std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
    const double middle = xs[xs.size() / 2], half = 0.5;  // a metre of the film's middle
    double speed = 0.0;
    size_t count = 0;
    for (const Particle& p : state.particles)
      if (std::fabs(p.px - middle) < half) {
        speed += p.vx;
        ++count;
      }
    const double h = double(count) * volume / (2.0 * half * kWidth);
    study.samples.push_back(
        {t, count ? speed / double(count) : 0.0, kG * 0.5 * h * h / (3.0 * nu)});
  });
  study.deviation = deviation(study.samples, 0.75 * seconds);
  return study;
}

// Martin & Moyce's column of width a and height 2a on a free-slip floor, against its back
// wall: the surge front (the farthest particle) / a against theirs for T from 1.5 to 3.
FlowStudy damBreak(const FlowStudyOptions& o) {
  const double nu = o.viscosity > 0.0 ? o.viscosity : 1e-6;
  constexpr float kA = 0.1f, kSpacing = kA / 20.0f;
  Scene s = latticeScene(nu, o.dt, kSpacing, 2.0f * kSpacing, 1000.0f, {0.5f * kA, kA, 0.0f},
                         {20.0f, 40.0f, 3.0f});
  s.friction = 1.0f;
  wall(s, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
  sides(s, 1.5f * kSpacing);
  const double scale = std::sqrt(2.0 * kG / kA);  // T per second
  std::vector<double> times;
  for (const auto& row : kMartinMoyce) times.push_back(row[0] / scale);
  FlowStudy study{"front / a", "Martin & Moyce (1952), n^2 = 2", {}, 0.0, 0.1};
  size_t k = 0;
  run(s, o, times, [&](double t, const State& state) {
    study.samples.push_back({t, front(state) / kA, kMartinMoyce[k++][1]});
  });
  for (const FlowSample& x : study.samples)
    if (x.t * scale >= 1.5 && x.t * scale <= 3.0)
      study.deviation = std::max(study.deviation, std::fabs(x.measured / x.published - 1.0));
  return study;
}

// A 2-D current of cross-section A = 0.02 m^2 released on a 30° slope with a no-slip ground:
// its front from the release's rear against Huppert's (9 A^2 g sin θ t / (4ν))^(1/3).
FlowStudy huppertSlope(const FlowStudyOptions& o) {
  const double nu = o.viscosity > 0.0 ? o.viscosity : 0.01;
  constexpr float kSpacing = 0.01f;
  Scene s = latticeScene(nu, o.dt, kSpacing, 2.0f * kSpacing, 2600.0f, {0.1f, 0.05f, 0.0f},
                         {20.0f, 10.0f, 4.0f});
  tilt(s, 30.0);
  s.friction = 0.0f;
  sides(s, 2.0f * kSpacing);
  const double area = 0.2 * 0.1, seconds = o.seconds > 0.0 ? o.seconds : 4.0;
  FlowStudy study{"front (m)", "Huppert (1982): (9 A^2 g sin(30°) t / (4 nu))^(1/3)", {}, 0.0, 0.1};
  run(s, o, every(seconds / 16.0, seconds), [&](double t, const State& state) {
    study.samples.push_back(
        {t, front(state), std::cbrt(9.0 * area * area * kG * 0.5 * t / (4.0 * nu))});
  });
  study.deviation = deviation(study.samples, 0.5 * seconds);
  return study;
}

// A pool released on flat ground with a no-slip base: its bulk front sqrt(7/3 <r^2>) about
// its centre (Huppert's r_N for his profile) against 0.894 (g V^3 t / (3ν))^(1/8).
FlowStudy huppertSpread(const FlowStudyOptions& o) {
  const double nu = o.viscosity > 0.0 ? o.viscosity : 0.1;
  constexpr float kSpacing = 0.02f;
  Scene s = latticeScene(nu, o.dt, kSpacing, 2.0f * kSpacing, 2600.0f, {0.0f, 0.15f, 0.0f},
                         {15.0f, 15.0f, 15.0f});
  s.friction = 0.0f;
  const double volume = 3375.0 * double(kSpacing) * kSpacing * kSpacing;
  const double seconds = o.seconds > 0.0 ? o.seconds : 10.0;
  const double similarity = std::pow(1024.0 / (81.0 * kPi * kPi * kPi), 0.125);  // 0.894
  FlowStudy study{"bulk front (m)", "Huppert (1982): 0.894 (g V^3 t / (3 nu))^(1/8)", {}, 0.0, 0.1};
  run(s, o, every(seconds / 20.0, seconds), [&](double t, const State& state) {
    double cx = 0.0, cz = 0.0;
    for (const Particle& p : state.particles) cx += p.px, cz += p.pz;
    const double n = double(state.particles.size());
    cx /= n;
    cz /= n;
    double r2 = 0.0;
    for (const Particle& p : state.particles)
      r2 += (p.px - cx) * (p.px - cx) + (p.pz - cz) * (p.pz - cz);
    study.samples.push_back(
        {t, std::sqrt(7.0 / 3.0 * r2 / n),
         similarity * std::pow(kG * std::pow(volume, 3.0) * t / (3.0 * nu), 0.125)});
  });
  study.deviation = deviation(study.samples, 0.5 * seconds);
  return study;
}

// A block of 10 x 10 x 10 lattice sites released at rest between four walls: its fastest
// particle at the end (the published value is rest; the tolerance 1 cm/s).
FlowStudy atRest(const FlowStudyOptions& o) {
  const double nu = o.viscosity > 0.0 ? o.viscosity : 0.05;
  constexpr float kSpacing = 0.02f, kHalf = 5.0f * kSpacing;
  Scene s = latticeScene(nu, o.dt, kSpacing, 2.0f * kSpacing, 2600.0f, {0.0f, kHalf, 0.0f},
                         {10.0f, 10.0f, 10.0f});
  wall(s, {-kHalf, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
  wall(s, {kHalf, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f});
  sides(s, kHalf);
  const double seconds = o.seconds > 0.0 ? o.seconds : 2.0;
  FlowStudy study{"fastest speed (m/s)", "at rest: below 0.01 m/s", {}, 0.0, 0.01};
  run(s, o, every(seconds / 8.0, seconds), [&](double t, const State& state) {
    double fastest = 0.0;
    for (const Particle& p : state.particles)
      fastest = std::max(
          fastest, std::sqrt(double(p.vx) * p.vx + double(p.vy) * p.vy + double(p.vz) * p.vz));
    study.samples.push_back({t, fastest, 0.0});
  });
  study.deviation = study.samples.back().measured;
  return study;
}

}  // namespace

FlowStudy studyFlow(const FlowStudyOptions& o) {
  if (o.name == "nusselt") return nusselt(o);
  if (o.name == "dam-break") return damBreak(o);
  if (o.name == "huppert-slope") return huppertSlope(o);
  if (o.name == "huppert-spread") return huppertSpread(o);
  if (o.name == "at-rest") return atRest(o);
  throw std::invalid_argument("expected one of " + std::string(kFlowCases) + ", got '" + o.name +
                              "'");
}

}  // namespace lava::app
