#include "camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace lava {

glm::vec3 OrbitCamera::eye() const {
  return target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                       std::cos(pitch) * std::cos(yaw));
}

glm::mat4 OrbitCamera::viewProj(float aspect) const {
  glm::mat4 projection = glm::perspectiveRH_ZO(fovY, aspect, 0.05f, 100.0f);
  projection[1][1] *= -1.0f;  // Vulkan's clip-space y points down
  return projection * glm::lookAt(eye(), target, glm::vec3(0.0f, 1.0f, 0.0f));
}

}  // namespace lava
