// The CPU reference, one particle at a time: the model written apart from the shaders, in
// plain float32 C++ built with -ffp-contract=off. CpuSimulation runs it over the rings;
// tests call it directly against closed forms.
#pragma once
#include <cstdint>

#include "lava/scene.h"
#include "lava/state.h"

namespace lava::detail {

// The particle of emitter `emitter` with serial number `serial`, at its birth.
void emitParticle(const Scene& scene, size_t emitter, uint64_t serial, Particle& particle);
// One step of a particle of emitter `emitter`; slots not alive are left as they are.
void stepParticle(const Scene& scene, size_t emitter, Particle& particle);

}  // namespace lava::detail
