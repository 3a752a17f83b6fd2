#include "resume.h"

#include "host/output.h"
#include "lava/error.h"
#include "lava/checkpoint.h"
#include "paths.h"

namespace lava::app {

std::optional<Snapshot> readResume(const Options& options, Scene& scene) {
  if (!options.given("resume")) return std::nullopt;
  if (options.given("scene"))
    throw UsageError("--scene: not with --resume (the checkpoint holds the scene)");
  try {
    Snapshot snapshot = readCheckpoint(options.text("resume"));
    scene = snapshot.scene;
    return snapshot;
  } catch (const InvalidArgument& e) {
    throw UsageError("--resume: " + std::string(e.what()));
  }
}

void checkResumedScene(const Scene& scene, const Scene& saved) {
  if (scene.emitters.size() != saved.emitters.size())
    throw UsageError("--resume: the checkpoint's scene has " +
                           std::to_string(saved.emitters.size()) + " emitters, not " +
                           std::to_string(scene.emitters.size()));
  for (size_t k = 0; k < saved.emitters.size(); ++k)
    if (scene.emitters[k].particles != saved.emitters[k].particles)
      throw UsageError(std::string(k == 0 ? "--particles" : "--resume") + ": " +
                             std::to_string(scene.emitters[k].particles) +
                             " disagrees with the checkpoint's " +
                             std::to_string(saved.emitters[k].particles) + " slots" +
                             (k == 0 ? "" : " for emitter " + std::to_string(k)) +
                             " (a resumed run keeps its emitters' capacities)");
}

}  // namespace lava::app
