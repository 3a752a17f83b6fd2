#version 460
// The ground plane (2 triangles) and a crater cone around the emitter (kCraterSides quads),
// generated from gl_VertexIndex: no vertex buffer.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push {
  DrawParams d;
};
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 normal;

const float kGroundHalf = 12.0;
const vec2 kQuad[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  uint i = uint(gl_VertexIndex);
  if (i < 6u) {
    vec2 c = (kQuad[i] * 2.0 - 1.0) * kGroundHalf;
    world = vec3(c.x, 0.0, c.y);
    normal = vec3(0, 1, 0);
  } else {
    uint quad = (i - 6u) / 6u;
    vec2 corner = kQuad[(i - 6u) % 6u];
    float angle = (float(quad) + corner.x) * (6.28318530718 / float(kCraterSides));
    float top = max(d.crater.y, 0.05);
    float rim = max(d.crater.w, 0.05) * 1.3;
    float base = rim + top * 1.8;
    float radius = mix(base, rim, corner.y);
    vec2 dir = vec2(cos(angle), sin(angle));
    world = vec3(d.crater.x + dir.x * radius, corner.y * top, d.crater.z + dir.y * radius);
    normal = normalize(vec3(dir.x * top, base - rim, dir.y * top));
  }
  gl_Position = d.viewProj * vec4(world, 1.0);
}
