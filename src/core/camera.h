// An orbit camera around the crater, producing Vulkan clip-space matrices.
#pragma once
#include <glm/glm.hpp>

namespace lava {

struct OrbitCamera {
  glm::vec3 target{0.0f, 1.0f, 0.0f};  // look-at point (m)
  float distance = 7.0f;               // from the target (m)
  float yaw = 0.6f;                    // around +y (rad)
  float pitch = 0.28f;                 // above the horizon (rad)
  float fovY = 0.8f;                   // vertical field of view (rad)

  glm::vec3 eye() const;
  // World (m) to Vulkan clip space (y down, depth 0..1).
  glm::mat4 viewProj(float aspect) const;
};

}  // namespace lava
