#include "lava/camera.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>

namespace lava {

Vec3 OrbitCamera::eye() const {
  const float c = std::cos(pitch);
  return {target.x + distance * c * std::sin(yaw), target.y + distance * std::sin(pitch),
          target.z + distance * c * std::cos(yaw)};
}

Mat4 OrbitCamera::viewProj(float aspect) const {
  glm::mat4 projection = glm::perspectiveRH_ZO(fovY, aspect, 0.05f, 100.0f);
  projection[1][1] *= -1.0f;  // Vulkan's clip-space y points down
  const Vec3 e = eye();
  const glm::mat4 m =
      projection * glm::lookAt(glm::vec3(e.x, e.y, e.z), glm::vec3(target.x, target.y, target.z),
                               glm::vec3(0.0f, 1.0f, 0.0f));
  Mat4 out;
  std::memcpy(out.m, glm::value_ptr(m), sizeof(out.m));
  return out;
}

}  // namespace lava
