#version 460
// One quad (two triangles, six vertices) per resolve tile of the target, clipped to it, for
// the tiles splat.comp marked; the vertices of the others fall on one point (clip.glsl's
// kNowhere) and draw nothing. Adjacent quads share their edges exactly: no pixel twice.
#extension GL_GOOGLE_include_directive : require
#include "clip.glsl"
#include "shared.h"

layout(std430, binding = kResolveMarksBinding) restrict readonly buffer Marks {
  uint marks[];
};
layout(push_constant) uniform Push {
  SplatParams s;
};

void main() {
  uint tile = uint(gl_VertexIndex) / 6u, corner = uint(gl_VertexIndex) % 6u;
  if (marks[tile] == 0u) {
    gl_Position = kNowhere;
    return;
  }
  uint tilesAcross = (s.target.x + kResolveTile - 1u) / kResolveTile;
  // Corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1).
  uvec2 c = uvec2(corner == 1u || corner >= 4u ? 1u : 0u,
                  corner == 2u || corner == 3u || corner == 5u ? 1u : 0u);
  uvec2 t = uvec2(tile % tilesAcross, tile / tilesAcross);
  uvec2 pixel = min((t + c) * kResolveTile, s.target.xy);
  gl_Position = vec4(vec2(pixel) / vec2(s.target.xy) * 2.0 - 1.0, 0.0, 1.0);
}
