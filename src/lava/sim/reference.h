// The CPU reference, one particle at a time: model-inl.h on one lane, the model written apart
// from the shaders in plain float32 C++ built with -ffp-contract=off. A Reference holds a
// scene with its host constants derived once; CpuSimulation runs it over the rings, cpu-simd
// (simd.h) over SIMD lanes, tests call it directly against closed forms.
#pragma once
#include <cstdint>
#include <vector>

#include "constants.h"
#include "emission.h"
#include "flow/lattice.h"
#include "lava/scene.h"
#include "lava/state.h"
#include "internal.h"

namespace lava::detail {

// Euler: the lab handout's crater scene (explicit Euler, no forces, colliders or lifetimes), stepped with
// the other modules' code left out. Any: everything.
enum class Modules { Euler, Any };

// Particles CpuSimulation steps together with the reference (they stay in L1).
constexpr size_t kReferenceBlock = 32;

class LAVA_INTERNAL Reference {
 public:
  explicit Reference(const Scene& scene);

  // The particle of emitter `emitter` with serial number `serial`, at its birth (a lattice
  // fill's serials are below its burst: the site of that index).
  void emit(size_t emitter, uint64_t serial, Particle& particle) const;
  // One step of a particle of emitter `emitter`; slots not alive are left as they are.
  void step(size_t emitter, Particle& particle) const;
  // Slots [first, first + count) of emitter `emitter`'s ring (all in `slots`) through the
  // steps of `schedule`: each step's births, then the step.
  void run(size_t emitter, const std::vector<Births>& schedule, uint32_t first, Particle* slots,
           size_t count) const;

  // The host constants, for the model (model-inl.h) and cpu-simd, which shares emit().
  const Scene& scene() const { return scene_; }
  Modules modules() const { return modules_; }
  const EmitterConstants& constants(size_t emitter) const { return emitters_[emitter]; }
  const Vec3& planeNormal(size_t collider) const { return normals_[collider]; }
  const ConeConstants& cone(size_t collider) const { return cones_[collider]; }

 private:
  template <Modules Use>
  void stepWith(size_t emitter, Particle& particle) const;
  template <Modules Use>
  void runWith(size_t emitter, const std::vector<Births>& schedule, uint32_t first, Particle* slots,
               size_t count) const;

  Scene scene_;
  Modules modules_;
  std::vector<EmitterConstants> emitters_;
  std::vector<Vec3> normals_;         // per collider: its plane's unit normal
  std::vector<ConeConstants> cones_;  // per collider: its cone's constants
  std::vector<Lattice> lattices_;     // per emitter: its lattice fill, if any
};

// Shorthands for single particles (tests).
void emitParticle(const Scene& scene, size_t emitter, uint64_t serial, Particle& particle);
void stepParticle(const Scene& scene, size_t emitter, Particle& particle);

}  // namespace lava::detail
