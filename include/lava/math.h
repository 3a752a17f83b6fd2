// The two value types of the API: a 3-vector of floats and a column-major 4x4 matrix
// (the layout of GLSL and glm, so `glm::value_ptr` converts either way).
#pragma once

namespace lava {

struct Vec3 {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
};

inline bool operator==(const Vec3& a, const Vec3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
inline bool operator!=(const Vec3& a, const Vec3& b) {
  return !(a == b);
}

struct Mat4 {
  float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // m[column * 4 + row]
};

}  // namespace lava
