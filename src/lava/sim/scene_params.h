// The scene as step.comp reads it: SceneParams (shaders/shared.h) packed from a Scene, and
// the specialization constants that leave the unused modules out of the pipeline.
#pragma once
#include "lava/scene.h"
#include "shared.h"
#include "vulkan/pipeline.h"
#include "internal.h"

namespace lava::detail {

LAVA_INTERNAL gpu::SceneParams sceneParams(const Scene& scene);
// Workgroup size, integrator, emitters, forces, colliders, lifetimes (shared.h's order).
LAVA_INTERNAL Constants stepConstants(const Scene& scene);

}  // namespace lava::detail
