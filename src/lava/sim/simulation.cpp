// What both backends share: the scene they were made for and its checks.
#include "lava/simulation.h"
#include "lava/error.h"

namespace lava {

Simulation::Simulation(const Scene& scene) : scene_(scene) {
  checkScene(scene_);
}

Simulation::~Simulation() = default;

void Simulation::setScene(const Scene& scene) {
  checkScene(scene);
  if (scene.emitters.size() != scene_.emitters.size())
    throw InvalidArgument("emitter", "a running simulation keeps its " +
                                         std::to_string(scene_.emitters.size()) + " emitters");
  for (size_t k = 0; k < scene.emitters.size(); ++k)
    if (scene.emitters[k].particles != scene_.emitters[k].particles)
      throw InvalidArgument(k == 0 ? "particles" : "emitter[" + std::to_string(k) + "].particles",
                            "a running simulation keeps its capacity (" +
                                std::to_string(scene_.emitters[k].particles) + ")");
  if (bool(scene.flow) != bool(scene_.flow))
    throw InvalidArgument("flow", std::string("a running simulation keeps ") +
                                      (scene_.flow ? "its flow" : "to no flow"));
  if (scene.flow && scene.flow->solver != scene_.flow->solver)
    throw InvalidArgument("flow.solver", std::string("a running simulation keeps its solver (") +
                                             lava::name(scene_.flow->solver) + ")");
  for (size_t k = 0; k < scene.emitters.size(); ++k)
    if (scene.emitters[k].flow != scene_.emitters[k].flow)
      throw InvalidArgument("emitter[" + std::to_string(k) + "].flow",
                            "a running simulation keeps which emitters are flow emitters");
  scene_ = scene;
}

}  // namespace lava
