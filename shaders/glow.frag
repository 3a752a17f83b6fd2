#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// The glow, interpolated between cell centres, for the blend src (1 - dst) + dst. Built with
// LAVA_GLOW_RESOLVE (glow_resolve.frag) it also resolves splat.comp's sums at the pixel, in
// one pass instead of resolve.frag's and this one's: the lines' colour a and the glow's g
// combine as the two blends would, 1 - (1 - a)(1 - g).
layout(location = 0) in vec3 color;
layout(location = 0) out vec4 outColor;
#if LAVA_GLOW_RESOLVE
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

#define LAVA_SUMS_BINDING kGlowDrawSumsBinding
#include "splat_sums.glsl"
layout(push_constant) uniform Push {
  GlowParams g;
};
#endif

void main() {
#if LAVA_GLOW_RESOLVE
  uvec2 p = uvec2(gl_FragCoord.xy);
  uint sum = splatSumAt(splatIndex(p.x, p.y, g.target.x));
  vec3 lines = sum == 0u ? vec3(0.0) : lavaSplatColor(sum, g.glow.z);
  outColor = vec4(lines + color - lines * color, 1.0);
#else
  outColor = vec4(color, 1.0);
#endif
}
