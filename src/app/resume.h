// --resume FILE.npz for simulate, validate and render: the checkpoint's scene as the base the flags
// change, and its state to start from.
#pragma once
#include <optional>

#include "lava/checkpoint.h"
#include "options.h"

namespace lava::app {

// Before options.resolve(): when --resume was given, reads the checkpoint (UsageError
// naming --resume when it is bad; --scene is refused) and sets `scene` to its scene.
std::optional<Snapshot> readResume(const Options& options, Scene& scene);
// After resolve(): flags may change a resumed scene's parameters, not its emitters or their
// capacities (UsageError naming --particles or --resume).
void checkResumedScene(const Scene& scene, const Scene& saved);

}  // namespace lava::app
