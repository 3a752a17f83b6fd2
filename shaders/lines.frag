#version 460
// A line's fragment: its colour, unless the flow's molten surface hides it.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(binding = kLineSurfaceBinding, rgba32f) uniform restrict readonly image2D filtered;
layout(push_constant) uniform Push {
  DrawParams d;
};
layout(location = 0) in vec4 color;
layout(location = 0) out vec4 outColor;

float surfaceDepth(ivec2 q) {
  return imageLoad(filtered, ivec2(2 * q.x, q.y)).x;
}
#include "surface_depth.glsl"

void main() {
  if (behindSurface(gl_FragCoord.xy, 1.0 / gl_FragCoord.w, d.surface)) discard;
  outColor = color;
}
