// What of SPEC §6 the backends implement so far: the §2 model (one disc emitter (bursts
// included) without lifetime, no forces or colliders, explicit Euler).
#pragma once
#include "lava/scene.h"

namespace lava::detail {

// Throws InvalidArgument naming the first part of `scene` the backends cannot run yet.
void requireSupported(const Scene& scene);

}  // namespace lava::detail
