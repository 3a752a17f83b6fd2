#version 460
// The molten surface's draw: a quad over each tile of surface pixels that a sphere touched
// (surface.comp's marks; vertex i is corner i % 6 of tile i / 6), clipped to the target;
// the other tiles draw nothing. surface.frag shades the pixels the flow covers and discards
// the rest. (On a CPU device a full-screen pass costs as much as a frame of lava.)
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "clip.glsl"

layout(std430, binding = kSurfaceDrawMarksBinding) restrict readonly buffer Marks {
  uint marks[];
};
layout(push_constant) uniform Push {
  SurfaceParams s;
};

const vec2 kCorners[6] =
    vec2[](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 0.0), vec2(1.0, 1.0),
           vec2(0.0, 1.0));

void main() {
  uint tile = uint(gl_VertexIndex) / 6u;
  uint across = (s.size.x + kSurfaceTile - 1u) / kSurfaceTile;
  if (marks[tile] == 0u) {
    gl_Position = kNowhere;
    return;
  }
  vec2 unit = kCorners[uint(gl_VertexIndex) % 6u];
  // A surface pixel more on each side: the quads overlap (opaque, the same shade twice)
  // rather than leave a target pixel between them where the target's size is odd.
  vec2 at = (vec2(uvec2(tile % across, tile / across)) + unit) * float(kSurfaceTile) +
            (2.0 * unit - 1.0);
  vec2 ndc = clamp(at / vec2(s.size.xy), vec2(0.0), vec2(1.0)) * 2.0 - 1.0;
  gl_Position = vec4(ndc, 0.5, 1.0);
}
