// A scene: everything that decides how particles are born, move and collide, as plain
// data with defaults (the lava crater of the lab handout). Both backends take the same
// Scene and compute the same float32 state from it.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "export.h"
#include "math.h"

namespace lava {

// Most emitters, forces and colliders one scene may have.
constexpr uint32_t kMaxEmitters = 16;
constexpr uint32_t kMaxForces = 16;
constexpr uint32_t kMaxColliders = 16;

// Where an emitter places a newborn particle around its position.
enum class Shape : uint32_t { Point, Disc, Sphere, Box };
enum class Integrator : uint32_t { ExplicitEuler, SemiImplicitEuler, VelocityVerlet };
enum class ForceType : uint32_t { Attractor, Vortex };
enum class ColliderType : uint32_t { Plane, Sphere, Box, Cone };
// How a flow emitter places its births: at random in its shape, launched (the default), or
// its one burst at rest on the cubic lattice of its spacing, centred in its box, sphere or
// disc (docs/model.md, "Lattice fill").
enum class Fill : uint32_t { Random, Lattice };
// The flow's method (docs/model.md, "The flow" and "The implicit flow"): a density constraint
// and viscosity solved implicitly in substeps, viscosity as given at any step (the default;
// the CPU backends step it, the GPU backend on the host), or weakly compressible SPH with
// explicit, capped viscosity (flow.comp on the GPU: every backend).
enum class FlowSolver : uint32_t { Explicit, Implicit };

// One emitter: a ring of `particles` slots of its own, reborn oldest first.
struct Emitter {
  uint32_t particles = 5000;        // ring capacity
  double rate = 1000.0;             // births per second (fractions carry over)
  uint32_t burst = 0;               // extra births at step 0 and every burstInterval
  double burstInterval = 0.0;       // s; 0: the burst happens at step 0 only
  Shape shape = Shape::Disc;        // disc: in the ground (x-z) plane
  Vec3 position{0.0f, 0.6f, 0.0f};  // m
  float radius = 0.15f;             // m, disc and sphere
  Vec3 size{0.1f, 0.1f, 0.1f};      // m, box half-extents
  Vec3 velocity{0.0f, 6.0f, 0.0f};  // mean launch velocity (m/s)
  Vec3 spread{1.6f, 1.5f, 1.6f};    // launch velocity spread per component (m/s)
  float mass = 1.0f;                // kg
  float lifetime = 0.0f;            // s; 0: lives until its slot is reborn
  bool flow = false;                // its particles are the flow's (Scene::flow)
  float temperature = 0.0f;         // K at birth, flow emitters; 0: the flow's temperature
  Fill fill = Fill::Random;         // flow emitters: Lattice takes one burst at step 0, rate 0
};

// A force added to gravity, wind and drag, in order.
struct Force {
  ForceType type = ForceType::Attractor;
  Vec3 position{0.0f, 2.0f, 0.0f};  // m: the attractor's point, the vortex's axis point
  Vec3 axis{0.0f, 1.0f, 0.0f};      // vortex: f += strength * (axis x (x - position))
  float strength = 5.0f;            // attractor: N/m; vortex: N/m per unit of axis
  float radius = 0.0f;              // attractor: acts within this distance; 0: everywhere
};

// A solid the particles bounce off, after the ground, in order.
struct Collider {
  ColliderType type = ColliderType::Plane;
  Vec3 position{};                // m: plane point, sphere/box centre, cone base centre
  Vec3 normal{0.0f, 1.0f, 0.0f};  // plane (any length but 0; Lava normalises it)
  float radius = 0.5f;            // sphere (m)
  Vec3 size{0.5f, 0.5f, 0.5f};    // box half-extents (m)
  float baseRadius = 1.0f;        // cone (m), at position.y
  float topRadius = 0.2f;         // cone (m), at position.y + height; <= baseRadius
  float height = 0.6f;            // cone (m)
  float restitution = 0.45f;      // normal speed kept (and reversed) by a bounce
  float friction = 0.7f;          // tangential velocity kept by a bounce
};

// The molten rock of the flow emitters: one material a scene (docs/model.md, "The flow").
struct Flow {
  float radius = 0.06f;           // m: flow particles closer than this interact
  float density = 2600.0f;        // kg/m^3 at rest: a particle's volume is mass / density
  float temperature = 1400.0f;    // K: the eruption's, each flow emitter's default
  float viscosity = 0.05f;        // kinematic viscosity (m^2/s) at and above `temperature`
  float viscositySolidus = 5.0f;  // m^2/s just above `solidus`
  float solidus = 1000.0f;        // K: at or below it a flow particle is solid
  float ambient = 300.0f;         // K: the air and the ground far away
  float coolingAir = 0.02f;       // 1/s: dT/dt = -coolingAir (T - ambient), always
  float coolingGround = 0.2f;     // 1/s: added while touching the ground or a collider
  float conduction = 0.0f;        // m^2/s: heat diffusivity between neighbours (0: none)
  float soundSpeed = 10.0f;       // m/s: the pressure's wave speed (at most 0.4 radius / h)
  float restitution = 0.0f;       // normal speed a flow particle keeps off the ground, colliders
  FlowSolver solver = FlowSolver::Implicit;
};

struct Scene {
  double dt = 0.001;          // step (s); the simulation steps by h = float(dt)
  float gravity = 9.81f;      // g (m/s^2), along -y
  float restitution = 0.45f;  // the ground (y = 0): normal speed kept by a bounce
  float friction = 0.7f;      // the ground: tangential velocity kept by a bounce
  Vec3 wind{};                // constant force (N)
  float drag = 0.0f;          // linear drag (N s/m)
  uint32_t seed = 20170101u;  // emitter k draws from the stream seed + k
  float lineScale = 0.04f;    // drawing: a particle is the line x -> x + lineScale v
  Integrator integrator = Integrator::ExplicitEuler;
  std::vector<Emitter> emitters = std::vector<Emitter>(1);  // the crater
  std::vector<Force> forces;
  std::vector<Collider> colliders;
  std::optional<Flow> flow;  // the [flow] table: set when any emitter is a flow emitter

  float h() const { return static_cast<float>(dt); }
  // Slots of all emitters together: the length of a state's particle array.
  LAVA_API uint64_t particles() const;
  // First slot of emitter k in the particle array (emitter 0's slots come first).
  LAVA_API uint64_t firstSlot(size_t emitter) const;
  // Steps of size h in `seconds` of simulated time (rounded to nearest).
  LAVA_API uint64_t stepsIn(double seconds) const;
  // Whether any emitter's particles are flow particles.
  LAVA_API bool flows() const;
};

// Throws InvalidArgument naming the first offending parameter ("emitter[1].radius").
// Every number that is not 0 must lie in [2^-20, 2^20] in magnitude (counts, rate and
// seed aside) on top of the range each parameter states.
LAVA_API void checkScene(const Scene& scene);

// -- Scene files (TOML) -----------------------------------------------------------------
//
// Format 2: top-level keys, then [[emitter]], [[force]] and [[collider]] tables and the
// [flow] table (docs/cli.md, "Scenes"). An emitter with `flow = true` in a file without
// [flow] gets the flow's defaults, and its `mass`, when the file does not give one,
// defaults to density * (radius / 2)^3: particles spaced half the radius apart.
// A file without [[emitter]] tables describes emitter 0 with the top-level emitter keys.

// For a top-level key Lava does not know: return true to accept it (a program's own
// option), false to reject it. `value` is its text form.
using OtherKey = std::function<bool(const std::string& key, const std::string& value)>;

// Reads a scene from TOML text; `name` is used in messages ("crater.toml: rate: ...").
// Throws InvalidArgument whose parameter is "<name>: <key>".
LAVA_API Scene parseScene(const std::string& toml, const std::string& name,
                          const OtherKey& other = {});
// The same from a file; a missing file or a folder is an InvalidArgument too.
LAVA_API Scene loadScene(const std::string& path, const OtherKey& other = {});
// Format 2 TOML that parseScene reads back into exactly this scene.
LAVA_API std::string toToml(const Scene& scene);

// Names as scene files spell them.
LAVA_API const char* name(Shape shape);
LAVA_API const char* name(Integrator integrator);
LAVA_API const char* name(ForceType type);
LAVA_API const char* name(ColliderType type);
LAVA_API const char* name(Fill fill);
LAVA_API const char* name(FlowSolver solver);

}  // namespace lava
