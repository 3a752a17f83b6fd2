#include "scene.h"

#include <cmath>

namespace lava {

uint64_t stepsIn(const Scene& scene, double seconds) {
  return static_cast<uint64_t>(std::llround(seconds / double(scene.dt)));
}

gpu::StepParams stepParams(const Scene& s) {
  gpu::StepParams p{};
  p.emitter = glm::vec4(s.emitter, s.emitterRadius);
  p.velocity = glm::vec4(s.velocity, s.dt);
  p.spread = glm::vec4(s.spread, s.gravity);
  p.wind = glm::vec4(s.wind, s.drag);
  p.material = glm::vec4(s.restitution, s.friction, s.mass, 0.0f);
  p.run = glm::uvec4(s.seed, s.particles, 0u, 0u);
  return p;
}

}  // namespace lava
