#version 460
// Dark basalt with a faint 1 m grid for scale, lit from above and warmed near the crater.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push {
  DrawParams d;
};
layout(location = 0) in vec3 world;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec4 outColor;

void main() {
  vec3 n = normalize(normal);
  float light = 0.35 + 0.65 * max(dot(n, normalize(vec3(0.3, 1.0, 0.2))), 0.0);
  bool cone = world.y > 0.001;
  vec3 rock = (cone ? vec3(0.16, 0.12, 0.10) : vec3(0.075, 0.065, 0.06)) * light;
  vec2 cell = abs(fract(world.xz) - 0.5);
  float line = step(0.485, max(cell.x, cell.y)) * step(world.y, 0.001);
  rock += vec3(0.03) * line;
  float near = exp(-length(world.xz - d.crater.xz) * 1.2);
  rock += vec3(0.35, 0.07, 0.0) * near * (0.4 + world.y);
  // Molten rim: the top of the cone glows.
  if (cone) rock += vec3(0.9, 0.25, 0.02) * smoothstep(0.75, 1.0, world.y / max(d.crater.y, 0.05));
  outColor = vec4(rock, 1.0);
}
