#version 460
// Dark basalt with a faint 1 m grid for scale on the ground, lit from above and warmed near
// the vent; the solids in lit stone, a cone's mouth glowing molten. The lava look shades in
// linear energy and tone maps it as the lines are (lava_color.glsl), then encodes it for
// the display: the rock lit by the eruption (a light above the vent) and the mouth glowing.
// (The sky is sky.vert's.)
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"
#include "solids.glsl"

layout(push_constant) uniform Push {
  BackdropParams b;
};
layout(location = 0) in vec3 world;
layout(location = 1) in vec3 normal;
layout(location = 2) in float height;
layout(location = 3) in vec3 rockLinear;  // ground.vert's: the lava look's rock, off the grid
layout(location = 4) in vec3 gridLinear;  // and on a grid line
layout(location = 0) out vec4 outColor;

void main() {
  uint kind = uint(b.solid.w);
  bool lava = b.eye.w == kLookLava;
  vec3 n = normalize(normal);
  // A wall seen from behind is left out: the camera looks into a room through it.
  if (kind == kSolidPlane && dot(n, b.eye.xyz - world) < 0.0) discard;
  float mouth = kind == kSolidCone ? smoothstep(0.75, 1.0, height) : 0.0;
  float line = kind == kSolidGround ? onGridLine(world) : 0.0;
  float near = exp(-length(world.xz - b.vent.xz) * 1.2);
  if (!lava) {
    vec3 rock = solidAlbedo(kind) * skyLight(n) + kGridLine * line;
    rock += vec3(0.35, 0.07, 0.0) * near * (0.4 + max(world.y, 0.0));
    rock += vec3(0.9, 0.25, 0.02) * mouth;  // the molten rim
    outColor = vec4(rock, 1.0);
    return;
  }
  vec3 rock = mix(rockLinear, gridLinear, line);
  vec3 toLight = b.vent.xyz + vec3(0.0, 0.35, 0.0) - world;
  float d2 = dot(toLight, toLight);
  float lit = max(dot(n, toLight * inversesqrt(max(d2, 1e-4))), 0.0) / (1.0 + 1.5 * d2);
  rock += vec3(0.55, 0.16, 0.035) * lit;                     // lit by the eruption
  rock += vec3(0.12, 0.025, 0.004) * near * near;             // embers around the vent
  rock += vec3(2.4, 0.75, 0.08) * mouth * mouth;              // the glowing mouth
  outColor = vec4(displayEncode(lavaToneMap(rock)), 1.0);
}
