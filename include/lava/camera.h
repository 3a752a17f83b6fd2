// An orbit camera around a target point: the view the `lava` program shows, offered to
// hosts as a convenience.
#pragma once
#include "export.h"
#include "math.h"

namespace lava {

struct OrbitCamera {
  Vec3 target{0.0f, 1.0f, 0.0f};  // look-at point (m)
  float distance = 7.0f;          // from the target (m)
  float yaw = 0.6f;               // around +y (rad)
  float pitch = 0.28f;            // above the horizon (rad)
  float fovY = 0.8f;              // vertical field of view (rad)

  LAVA_API Vec3 eye() const;
  // World (m) to Vulkan clip space (y down, depth 0..1) for a target of this aspect.
  LAVA_API Mat4 viewProj(float aspect) const;
};

}  // namespace lava
