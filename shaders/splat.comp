#version 460
// The fast line renderer: each alive particle walks its line x → x + s·v in screen space
// and adds its color into a fixed-point accumulation buffer with atomics (additive glow).
// Software rasterisers draw lines one primitive at a time; this is one invocation each.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = 0) restrict readonly buffer Particles {
  Particle particles[];
};
layout(std430, binding = 1) restrict buffer Accumulation {
  uint accumulation[];
};
layout(push_constant) uniform Push {
  SplatParams s;
};

const uint kMaxPixels = 256u;  // longer lines are cut (they are rare and off-scale anyway)

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= s.target.z) return;
  Particle q = particles[i];
  if (q.posAge.w < 0.0) return;  // never emitted: draws nothing
  vec3 v = q.velMass.xyz;
  vec4 a = s.viewProj * vec4(q.posAge.xyz, 1.0);
  vec4 b = s.viewProj * vec4(q.posAge.xyz + s.style.x * v, 1.0);
  if (a.w <= 0.05 || b.w <= 0.05) return;  // behind the camera
  vec2 size = vec2(s.target.xy);
  vec2 pa = (a.xy / a.w * 0.5 + 0.5) * size;
  vec2 pb = (b.xy / b.w * 0.5 + 0.5) * size;
  vec2 d = pb - pa;
  uint n = min(uint(max(abs(d.x), abs(d.y))), kMaxPixels - 1u) + 1u;
  vec3 c = lavaColor(v, q.posAge.w, s.style);
  uint add = (uint(c.r * kSplatScale + 0.5) << 16) | uint(c.g * kSplatScale + 0.5);
  vec2 step = d / float(n);
  vec2 at = pa;
  for (uint k = 0u; k < n; ++k, at += step) {
    uvec2 p = uvec2(ivec2(floor(at)));  // negative wraps to huge: one unsigned test per axis
    if (p.x < s.target.x && p.y < s.target.y) atomicAdd(accumulation[p.y * s.target.x + p.x], add);
  }
}
