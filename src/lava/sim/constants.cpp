#include "constants.h"

#include <algorithm>
#include <cmath>

namespace lava::detail {

EmitterConstants emitterConstants(const Scene& scene, size_t emitter) {
  const float h = scene.h();
  const float m = scene.emitters[emitter].mass;
  const float hm = h / m;
  return {hm, (0.5f * h) * hm, 0.5f * hm, scene.wind.y - m * scene.gravity};
}

Vec3 unitNormal(const Vec3& n) {
  const double x = n.x, y = n.y, z = n.z;
  const double length = std::sqrt(x * x + y * y + z * z);
  return {float(x / length), float(y / length), float(z / length)};
}

ConeConstants coneConstants(const Collider& c) {
  const double base = c.baseRadius, top = c.topRadius, height = c.height;
  const double side = std::sqrt(height * height + (base - top) * (base - top));
  // 2^-13 of the cone's size: far above float rounding at its scale, far below a pixel.
  const double margin = std::max(base, height) / 8192.0;
  return {float((top - base) / height), float(height / side), float((base - top) / side),
          float(double(c.position.y) + height + margin), float(margin)};
}

}  // namespace lava::detail
