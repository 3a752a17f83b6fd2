#version 460
// The lava look's sky: a night sky fading into a warm haze at the horizon, in kSkyBands
// horizontal bands over the screen at the far plane, drawn after the solids (the depth test
// leaves what they cover unshaded) with lines.frag's interpolated colour. Band k spans
// heights (0 at the bottom of the screen, 1 at its top) from edge k to edge k + 1: edge 0 is
// the bottom, edges 1 to kSkyBands run from the haze's edge (a quarter up; below it the sky
// is one colour) to the top. The gradient is smooth, so its colour at the edges,
// interpolated, is its colour at every pixel within 0.3 of a display step, and a pixel
// costs no more than a line's.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(location = 0) out vec4 color;

const vec2 kQuad[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  uint i = uint(gl_VertexIndex);
  vec2 corner = kQuad[i % 6u];
  uint edge = i / 6u + uint(corner.y);
  float height = edge == 0u ? 0.0 : mix(0.25, 1.0, float(edge - 1u) / float(kSkyBands - 1u));
  gl_Position = vec4(corner.x * 2.0 - 1.0, 1.0 - 2.0 * height, 1.0, 1.0);
  vec3 zenith = vec3(0.0015, 0.0018, 0.006), haze = vec3(0.030, 0.011, 0.006);
  vec3 sky = mix(haze, zenith, smoothstep(0.25, 1.0, height));
  color = vec4(pow(lavaToneMap(sky), vec3(1.0 / 2.2)), 1.0);
}
