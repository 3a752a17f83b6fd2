#version 460
// The fast line renderer: each alive particle walks its line x → x + s·v in screen space
// and adds its color into a fixed-point accumulation buffer with atomics (additive glow).
// Software rasterisers draw lines one primitive at a time; this is one invocation each.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(local_size_x_id = 0) in;

// The particles as RGBA32F texels (posAge, velMass): llvmpipe gathers texel fetches
// without the per-lane bounds-checked loop it runs for a storage-buffer load.
layout(binding = kSplatParticleBinding) uniform samplerBuffer particles;
layout(std430, binding = kSplatSumsBinding) restrict buffer Accumulation {
  uint accumulation[];
};
layout(push_constant) uniform Push {
  SplatParams s;
};

const uint kMaxPixels = 256u;  // longer lines are cut (they are rare and off-scale anyway)

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= s.target.z) return;
  Particle q = Particle(texelFetch(particles, int(2u * i)), texelFetch(particles, int(2u * i + 1u)));
  if (q.posAge.w < 0.0) return;  // never emitted: draws nothing
  vec3 v = q.velMass.xyz;
  vec4 a = s.viewProj * vec4(q.posAge.xyz, 1.0);
  vec4 b = s.viewProj * vec4(q.posAge.xyz + s.style.x * v, 1.0);
  if (a.w <= 0.05 || b.w <= 0.05) return;  // behind the camera
  vec2 size = vec2(s.target.xy);
  vec2 pa = (a.xy / a.w * 0.5 + 0.5) * size;
  vec2 pb = (b.xy / b.w * 0.5 + 0.5) * size;
  // Like a rasteriser's line: one pixel per pixel centre the line passes along its major
  // axis, sampled at those centres (half-open, [a, b)), so a line shorter than a pixel, such
  // as a particle resting on the ground, usually draws nothing, as in the graphics pipeline.
  vec2 d = pb - pa;
  bool xMajor = abs(d.x) >= abs(d.y);
  float a0 = xMajor ? pa.x : pa.y, a1 = xMajor ? pb.x : pb.y;
  float m0 = xMajor ? pa.y : pa.x, m1 = xMajor ? pb.y : pb.x;
  float majorSize = float(xMajor ? s.target.x : s.target.y);
  // Clipped to the target along the major axis (in floats first: no int overflow).
  int first = int(ceil(clamp(min(a0, a1), 0.0, majorSize) - 0.5));
  int end = int(ceil(clamp(max(a0, a1), 0.0, majorSize) - 0.5));
  if (end <= first) return;
  uint n = min(uint(end - first), kMaxPixels);
  float slope = (m1 - m0) / (a1 - a0);  // a1 != a0: at least one centre lies between them
  float minor = m0 + (float(first) + 0.5 - a0) * slope;
  uint minorSize = xMajor ? s.target.y : s.target.x;
  vec3 c = lavaColor(v, q.posAge.w, s.style);
  uint add = (uint(c.r * kSplatScale + 0.5) << 16) | uint(c.g * kSplatScale + 0.5);
  for (uint k = 0u; k < n; ++k, minor += slope) {
    uint major = uint(first) + k;
    uint across = uint(int(floor(minor)));  // negative wraps to huge: one unsigned test
    if (across < minorSize) {
      uvec2 p = xMajor ? uvec2(major, across) : uvec2(across, major);
      atomicAdd(accumulation[p.y * s.target.x + p.x], add);
    }
  }
}
