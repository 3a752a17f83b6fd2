#version 460
// Turns splat.comp's fixed-point sums into color, blended additively over the ground.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(std430, binding = kResolveSumsBinding) restrict readonly buffer Accumulation {
  uint accumulation[];
};
layout(push_constant) uniform Push {
  SplatParams s;
};
layout(location = 0) out vec4 outColor;

void main() {
  uvec2 p = uvec2(gl_FragCoord.xy);
  uint sum = accumulation[p.y * s.target.x + p.x];
  if (sum == 0u) discard;
  float r = float(sum >> 16) / kSplatScale;
  float g = float(sum & 0xffffu) / kSplatScale;
  outColor = vec4(r, g, 0.06 * r, 1.0);
}
