#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// The glow's listed quads (6 vertices each), each spanning the centres of four neighbouring
// cells (the screen's edges clamped), with each corner's light tone mapped: the rasteriser
// interpolates between cell centres, and a pixel costs no more than a line's.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(std430, binding = kGlowDrawListBinding) restrict readonly buffer List {
  uint command[4];
  uint quads[];
};
// The light, one RG32F texel a cell; built without LAVA_GLOW_TEXELS (where a texel view
// cannot hold the cells), the storage buffer glow.comp wrote.
#if LAVA_GLOW_TEXELS
layout(binding = kGlowDrawLightBinding) uniform textureBuffer light;

vec2 lightAt(int cell) {
  return texelFetch(light, cell).rg;
}
#else
layout(std430, binding = kGlowDrawLightBinding) restrict readonly buffer Light {
  vec2 light[];
};

vec2 lightAt(int cell) {
  return light[cell];
}
#endif
layout(push_constant) uniform Push {
  GlowParams g;
};
layout(location = 0) out vec3 color;

const uvec2 kQuad[6] = uvec2[](uvec2(0, 0), uvec2(1, 0), uvec2(1, 1), uvec2(0, 0), uvec2(1, 1), uvec2(0, 1));

void main() {
  uint quad = quads[gl_VertexIndex / 6];
  uvec2 corner = uvec2(quad % (g.grid.x + 1u), quad / (g.grid.x + 1u)) + kQuad[gl_VertexIndex % 6];
  // Corner k of the dual grid is the centre of cell k - 1 (clamped: the edges' half cells).
  vec2 pixel = clamp((vec2(corner) - 0.5) * float(kGlowCell), vec2(0.0), vec2(g.target.xy));
  ivec2 cell = clamp(ivec2(corner) - 1, ivec2(0), ivec2(g.grid.xy) - 1);
  vec2 e = lightAt(cell.y * int(g.grid.x) + cell.x);
  color = lavaToneMap(lavaEnergy(e) * g.glow.z);
  gl_Position = vec4(pixel / vec2(g.target.xy) * 2.0 - 1.0, 0.0, 1.0);
}
