#version 460
// Dark basalt with a faint 1 m grid for scale on the ground, lit from above and warmed near
// the vent; the solids in lit stone, a cone's mouth glowing molten.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push {
  BackdropParams b;
};
layout(location = 0) in vec3 world;
layout(location = 1) in vec3 normal;
layout(location = 2) in float height;
layout(location = 0) out vec4 outColor;

void main() {
  vec3 n = normalize(normal);
  // A wall seen from behind is left out: the camera looks into a room through it.
  if (uint(b.solid.w) == kSolidPlane && dot(n, b.eye.xyz - world) < 0.0) discard;
  float light = 0.35 + 0.65 * max(dot(n, normalize(vec3(0.3, 1.0, 0.2))), 0.0);
  uint kind = uint(b.solid.w);
  vec3 rock;
  if (kind == kSolidGround) {
    rock = vec3(0.075, 0.065, 0.06) * light;
    vec2 cell = abs(fract(world.xz) - 0.5);
    rock += vec3(0.03) * step(0.485, max(cell.x, cell.y));
  } else if (kind == kSolidCone) {
    rock = vec3(0.16, 0.12, 0.10) * light;
    rock += vec3(0.9, 0.25, 0.02) * smoothstep(0.75, 1.0, height);  // the molten mouth
  } else {
    rock = vec3(0.20, 0.19, 0.18) * light;
  }
  float near = exp(-length(world.xz - b.vent.xz) * 1.2);
  rock += vec3(0.35, 0.07, 0.0) * near * (0.4 + max(world.y, 0.0));
  outColor = vec4(rock, 1.0);
}
