#version 460
// The backdrop's solids from gl_VertexIndex, no vertex buffer: the ground plane, and the
// colliders (a cone with its cap, a sphere, a box, a square of a plane), one draw each.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "solids.glsl"

layout(push_constant) uniform Push {
  BackdropParams b;
};
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 normal;
layout(location = 2) out float height;  // 0 at a cone's base, 1 at its top
// The lava look's rock under the sky light, in linear energy, off and on the ground's grid
// lines: smooth over a solid, so a vertex's is interpolated instead of a pow per pixel.
layout(location = 3) out vec3 rockLinear;
layout(location = 4) out vec3 gridLinear;

const float kGroundHalf = 12.0;
const float kPlaneHalf = 4.0;
const float kTau = 6.28318530718;
const vec2 kQuad[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

vec3 around(float turns) {
  return vec3(cos(turns * kTau), 0.0, sin(turns * kTau));
}

void cone(uint i, out vec3 p, out vec3 n) {
  const float base = b.size.x, top = b.size.y, h = b.size.z;
  height = 0.0;
  if (i < 6u * kRoundSides) {  // the side
    vec2 c = kQuad[i % 6u];
    vec3 dir = around((float(i / 6u) + c.x) / float(kRoundSides));
    p = dir * mix(base, top, c.y) + vec3(0.0, c.y * h, 0.0);
    n = normalize(dir * h + vec3(0.0, base - top, 0.0));
    height = c.y;
  } else {  // the top cap
    uint j = i - 6u * kRoundSides;
    uint corner = j % 3u;
    p = corner == 0u ? vec3(0.0) : around((float(j / 3u) + float(corner - 1u)) / float(kRoundSides)) * top;
    p.y = h;
    n = vec3(0.0, 1.0, 0.0);
    height = 1.0;
  }
}

void sphere(uint i, out vec3 p, out vec3 n) {
  vec2 c = kQuad[i % 6u];
  uint quad = i / 6u;
  float turns = (float(quad % kRoundSides) + c.x) / float(kRoundSides);
  float up = ((float(quad / kRoundSides) + c.y) / float(kSphereRings) - 0.5) * 3.14159265359;
  n = around(turns) * cos(up) + vec3(0.0, sin(up), 0.0);
  p = n * b.size.x;
  height = 0.0;
}

void box(uint i, out vec3 p, out vec3 n) {
  uint face = i / 6u;  // -x +x -y +y -z +z
  uint axis = face / 2u;
  float side = (face % 2u) == 0u ? -1.0 : 1.0;
  vec2 c = kQuad[i % 6u] * 2.0 - 1.0;
  vec3 q = vec3(0.0);
  q[axis] = side;
  q[(axis + 1u) % 3u] = c.x;
  q[(axis + 2u) % 3u] = c.y;
  n = vec3(0.0);
  n[axis] = side;
  p = q * b.size.xyz;
  height = 0.0;
}

void plane(uint i, out vec3 p, out vec3 n) {
  n = b.size.xyz;
  vec3 t = normalize(abs(n.y) < 0.9 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
  vec3 s = cross(n, t);
  vec2 c = (kQuad[i] * 2.0 - 1.0) * kPlaneHalf;
  p = t * c.x + s * c.y;
  height = 0.0;
}

void main() {
  uint i = uint(gl_VertexIndex);
  uint kind = uint(b.solid.w);
  vec3 p, n;
  if (kind == kSolidCone) {
    cone(i, p, n);
  } else if (kind == kSolidSphere) {
    sphere(i, p, n);
  } else if (kind == kSolidBox) {
    box(i, p, n);
  } else if (kind == kSolidPlane) {
    plane(i, p, n);
  } else {
    vec2 c = (kQuad[i] * 2.0 - 1.0) * kGroundHalf;
    p = vec3(c.x, 0.0, c.y);
    n = vec3(0.0, 1.0, 0.0);
    height = 0.0;
  }
  world = b.solid.xyz + p;
  normal = n;
  gl_Position = b.viewProj * vec4(world, 1.0);
  vec3 rock = solidAlbedo(kind) * skyLight(n);
  rockLinear = pow(rock, vec3(2.2)) * 0.8;
  gridLinear = kind == kSolidGround ? pow(rock + kGridLine, vec3(2.2)) * 0.8 : rockLinear;
}
