#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// Turns splat.comp's fixed-point sums into colour over the scene: in the plain look the
// lab handout's colour (blue a tint of red), added; in the lava look the energy tone mapped, for
// the pipeline's blend src (1 - dst) + dst (lava_color.glsl).
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

#define LAVA_SUMS_BINDING kResolveSumsBinding
#include "splat_sums.glsl"
layout(push_constant) uniform Push {
  SplatParams s;
};
layout(location = 0) out vec4 outColor;

void main() {
  uvec2 p = uvec2(gl_FragCoord.xy);
  uint at = splatIndex(p.x, p.y, s.target.x);
  uint sum = splatSumAt(at);
  if (sum == 0u) discard;
  vec2 rg = splatSums(sum);
  outColor = s.style.w == kLookLava ? vec4(lavaSplatColor(sum, s.look.x), 1.0)
                                    : vec4(rg, 0.06 * rg.r, 1.0);
}
