// The scene's derived figures, its validation, and the names of its enums.
#include <cmath>

#include "flow/lattice.h"
#include "keys.h"
#include "lava/error.h"
#include "lava/scene.h"
#include "lava/scene_keys.h"

namespace lava {

uint64_t Scene::particles() const {
  uint64_t total = 0;
  for (const Emitter& e : emitters) total += e.particles;
  return total;
}

uint64_t Scene::firstSlot(size_t emitter) const {
  uint64_t first = 0;
  for (size_t k = 0; k < emitter && k < emitters.size(); ++k) first += emitters[k].particles;
  return first;
}

bool Scene::flows() const {
  for (const Emitter& e : emitters)
    if (e.flow) return true;
  return false;
}

uint64_t Scene::stepsIn(double seconds) const {
  return static_cast<uint64_t>(std::llround(seconds / double(h())));
}

namespace {

void checkTable(const Scene& scene, KeyTable table, size_t count, const char* prefix) {
  for (size_t i = 0; i < count; ++i)
    for (const detail::KeyDef& d : detail::keyDefs(table))
      d.check(scene, i, std::string(prefix) + "[" + std::to_string(i) + "]." + d.key.name);
}

void checkCount(size_t count, uint32_t most, const char* table) {
  if (count > most)
    throw InvalidArgument(table, "at most " + std::to_string(most) + " [[" + table +
                                     "]] tables, got " + std::to_string(count));
}

// A lattice fill is one burst at step 0 of a flow emitter, no larger than its lattice.
void checkLattice(const Scene& scene, size_t k) {
  const Emitter& e = scene.emitters[k];
  if (e.fill != Fill::Lattice) return;
  const std::string at = "emitter[" + std::to_string(k) + "].";
  const std::string why = "fill = \"lattice\" places one burst at step 0";
  if (e.rate != 0.0)
    throw InvalidArgument(at + "rate", "expected 0 with " + why + ", got " +
                                           detail::formatDouble(e.rate));
  if (e.burstInterval != 0.0)
    throw InvalidArgument(at + "burst-interval", "expected 0 with " + why + ", got " +
                                                     detail::formatDouble(e.burstInterval));
  const uint64_t sites = detail::flowLattice(scene, k).sites;
  if (e.burst < 1 || e.burst > sites)
    throw InvalidArgument(at + "burst",
                          "expected 1 to " + std::to_string(sites) + " with " + why + ": " +
                              std::to_string(sites) + " sites of " +
                              detail::formatFloat(float(std::cbrt(double(e.mass) /
                                                                  double(scene.flow->density)))) +
                              " m fit in its " + name(e.shape) + ", got " +
                              std::to_string(e.burst));
}

// The flow's keys and how they bound each other and the flow emitters' masses.
void checkFlow(const Scene& scene) {
  for (size_t k = 0; k < scene.emitters.size(); ++k)
    if (scene.emitters[k].fill == Fill::Lattice && !scene.emitters[k].flow)
      throw InvalidArgument("emitter[" + std::to_string(k) + "].fill",
                            "\"lattice\" fills a flow emitter (flow = true): its spacing is "
                            "(mass / flow.density)^(1/3)");
  if (!scene.flow) {
    for (size_t k = 0; k < scene.emitters.size(); ++k)
      if (scene.emitters[k].flow)
        throw InvalidArgument("emitter[" + std::to_string(k) + "].flow",
                              "a flow emitter needs the scene's flow (the [flow] table)");
    return;
  }
  const Flow& f = *scene.flow;
  for (const detail::KeyDef& d : detail::keyDefs(KeyTable::Flow))
    d.check(scene, 0, "flow." + d.key.name);
  using detail::formatFloat;
  if (!(f.solidus < f.temperature))
    throw InvalidArgument("flow.solidus", "expected below flow.temperature (" +
                                              formatFloat(f.temperature) + "), got " +
                                              formatFloat(f.solidus));
  if (f.viscositySolidus < f.viscosity)
    throw InvalidArgument("flow.viscosity-solidus",
                          "expected at least flow.viscosity (" + formatFloat(f.viscosity) +
                              "): the flow stiffens as it cools, got " +
                              formatFloat(f.viscositySolidus));
  if ((double(f.coolingAir) + double(f.coolingGround)) * double(scene.h()) > 1.0)
    throw InvalidArgument("flow.cooling-ground",
                          "(cooling-air + cooling-ground) * dt must be at most 1, got (" +
                              formatFloat(f.coolingAir) + " + " + formatFloat(f.coolingGround) +
                              ") * " + detail::formatDouble(scene.dt));
  // Particles spaced between radius/6 and 3 radius/4: a neighbourhood the sums resolve, and
  // not thousands of neighbours.
  const double lo = double(f.radius) / 6.0, hi = 0.75 * double(f.radius);
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    const Emitter& e = scene.emitters[k];
    if (!e.flow) continue;
    const double spacing = std::cbrt(double(e.mass) / double(f.density));
    if (spacing < lo || spacing > hi)
      throw InvalidArgument(
          "emitter[" + std::to_string(k) + "].mass",
          "a flow particle of " + formatFloat(e.mass) + " kg at flow.density " +
              formatFloat(f.density) + " kg/m^3 is " + formatFloat(float(spacing)) +
              " m across; expected radius/6 to 3 radius/4: a mass in [" +
              formatFloat(float(double(f.density) * lo * lo * lo)) + ", " +
              formatFloat(float(double(f.density) * hi * hi * hi)) + "] kg (a table without " +
              "mass gets " + formatFloat(detail::defaultFlowMass(f)) + ")");
  }
  for (size_t k = 0; k < scene.emitters.size(); ++k) checkLattice(scene, k);
}

}  // namespace

void checkScene(const Scene& scene) {
  for (const detail::KeyDef& d : detail::keyDefs(KeyTable::Top))
    if (!d.emitterZero) d.check(scene, 0, d.key.name);
  if (scene.emitters.empty())
    throw InvalidArgument("emitter", "a scene needs at least one emitter");
  checkCount(scene.emitters.size(), kMaxEmitters, "emitter");
  checkCount(scene.forces.size(), kMaxForces, "force");
  checkCount(scene.colliders.size(), kMaxColliders, "collider");
  checkTable(scene, KeyTable::Emitter, scene.emitters.size(), "emitter");
  checkTable(scene, KeyTable::Force, scene.forces.size(), "force");
  checkTable(scene, KeyTable::Collider, scene.colliders.size(), "collider");
  checkFlow(scene);
  if (scene.particles() > (uint64_t{1} << 31))
    throw InvalidArgument("particles", "the emitters hold " + std::to_string(scene.particles()) +
                                           " slots together; at most 2^31");
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    const std::string at = "collider[" + std::to_string(i) + "].";
    if (c.type == ColliderType::Plane && c.normal == Vec3{})
      throw InvalidArgument(at + "normal", "expected a non-zero vector, got 0,0,0");
    if (c.type == ColliderType::Cone && c.topRadius > c.baseRadius)
      throw InvalidArgument(at + "top-radius", "expected at most base-radius (" +
                                                   detail::formatFloat(c.baseRadius) + "), got " +
                                                   detail::formatFloat(c.topRadius));
  }
}

size_t emitterOf(const Scene& scene, uint64_t slot) {
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    if (slot < scene.emitters[k].particles) return k;
    slot -= scene.emitters[k].particles;
  }
  return scene.emitters.empty() ? 0 : scene.emitters.size() - 1;
}

const char* name(Shape shape) {
  switch (shape) {
    case Shape::Point:
      return "point";
    case Shape::Disc:
      return "disc";
    case Shape::Sphere:
      return "sphere";
    case Shape::Box:
      return "box";
  }
  return "?";
}

const char* name(Integrator integrator) {
  switch (integrator) {
    case Integrator::ExplicitEuler:
      return "explicit-euler";
    case Integrator::SemiImplicitEuler:
      return "semi-implicit-euler";
    case Integrator::VelocityVerlet:
      return "velocity-verlet";
  }
  return "?";
}

const char* name(ForceType type) {
  switch (type) {
    case ForceType::Attractor:
      return "attractor";
    case ForceType::Vortex:
      return "vortex";
  }
  return "?";
}

const char* name(ColliderType type) {
  switch (type) {
    case ColliderType::Plane:
      return "plane";
    case ColliderType::Sphere:
      return "sphere";
    case ColliderType::Box:
      return "box";
    case ColliderType::Cone:
      return "cone";
  }
  return "?";
}

const char* name(Fill fill) {
  switch (fill) {
    case Fill::Random:
      return "random";
    case Fill::Lattice:
      return "lattice";
  }
  return "?";
}

const char* name(FlowSolver solver) {
  switch (solver) {
    case FlowSolver::Explicit:
      return "explicit";
    case FlowSolver::Implicit:
      return "implicit";
  }
  return "?";
}

}  // namespace lava
