#version 460
// The lava look's glow, at one cell per kGlowCell x kGlowCell pixels, in three passes
// (specialization constant 1):
// - splat: every stride-th alive particle adds its line's energy (times the stride) into
//   the cell of the line's middle, in fixed point (two planes of uint, red and green);
// - blur: each cell's energy per pixel above the threshold (the brightest channel less the
//   threshold, the hue kept: only what glows brightly spreads), blurred over 5 x 5 cells
//   and times the strength: the light each cell receives;
// - list: the quads between four neighbouring cells' centres (one more across and down than
//   cells, the edges clamped) where any of the four has visible light, appended to the list
//   (its vertex count 6 per quad); and the sums cleared for the slot's next frame.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint kPass = kGlowSplat;

layout(binding = kGlowParticlesBinding) uniform samplerBuffer particles;
layout(std430, binding = kGlowSumsBinding) restrict buffer Sums {
  uint sums[];  // red cells, then green cells
};
layout(std430, binding = kGlowLightBinding) restrict buffer Light {
  vec2 light[];
};
layout(std430, binding = kGlowListBinding) restrict buffer List {
  uint vertexCount;  // VkDrawIndirectCommand
  uint instanceCount;
  uint firstVertex;
  uint firstInstance;
  uint cells[];  // the quads to draw
};
layout(binding = kGlowSumTexelsBinding) uniform usamplerBuffer sumTexels;  // the sums again
layout(push_constant) uniform Push {
  GlowParams g;
};

const float kFixed = 256.0;  // sums: energy x kFixed
const float kVisible = 0.002;  // glow energy below this adds less than half a display step
// A 5-tap Gaussian (sigma 1 cell), normalised.
const int kTaps = 3;
const float kWeights[kTaps] = float[](0.4026, 0.2442, 0.0545);

vec2 thresholded(uint cell) {
  uint n = g.grid.x * g.grid.y;
  // Read as texels: on llvmpipe a gather, where a storage-buffer load is a loop over lanes.
  vec2 e = vec2(float(texelFetch(sumTexels, int(cell)).r), float(texelFetch(sumTexels, int(n + cell)).r)) *
           (1.0 / (kFixed * float(kGlowCell * kGlowCell)));
  float peak = max(e.r, e.g);
  return peak > g.glow.x ? e * ((peak - g.glow.x) / peak) : vec2(0.0);
}

void splat() {
  if (gl_GlobalInvocationID.x == 0u && g.target.z == 1u) {  // the first chunk's first
    vertexCount = 0u;  // the list's draw arguments: no vertices yet, one instance
    instanceCount = 1u;
    firstVertex = 0u;
    firstInstance = 0u;
  }
  uint i = gl_GlobalInvocationID.x * g.grid.w;
  if (i >= g.grid.z) return;
  vec4 posAge = texelFetch(particles, int(2u * i));
  if (posAge.w < 0.0) return;
  vec3 v = texelFetch(particles, int(2u * i + 1u)).xyz;
  vec4 a = g.viewProj * vec4(posAge.xyz, 1.0);
  vec4 b = g.viewProj * vec4(posAge.xyz + g.style.x * v, 1.0);
  if (a.w <= 0.05 || b.w <= 0.05) return;
  vec2 size = vec2(g.target.xy);
  vec2 pa = (a.xy / a.w * 0.5 + 0.5) * size, pb = (b.xy / b.w * 0.5 + 0.5) * size;
  vec2 mid = 0.5 * (pa + pb);
  if (any(lessThan(mid, vec2(0.0))) || any(greaterThanEqual(mid, size))) return;
  float pixels = clamp(length(pb - pa), 1.0, 256.0);  // as the splat draws it
  vec2 e = lavaEmission(v, posAge.w, g.style) * (pixels * float(g.grid.w) * kFixed);
  uvec2 c = min(uvec2(mid) / kGlowCell, g.grid.xy - 1u);
  uint cell = c.y * g.grid.x + c.x;
  atomicAdd(sums[cell], uint(e.r + 0.5));
  atomicAdd(sums[g.grid.x * g.grid.y + cell], uint(e.g + 0.5));
}

void blur(uvec2 c, uint cell) {
  vec2 sum = vec2(0.0);
  for (int dy = 1 - kTaps; dy < kTaps; ++dy) {
    int y = int(c.y) + dy;
    if (y < 0 || y >= int(g.grid.y)) continue;
    vec2 row = vec2(0.0);
    for (int dx = 1 - kTaps; dx < kTaps; ++dx) {
      int x = int(c.x) + dx;
      if (x >= 0 && x < int(g.grid.x)) row += thresholded(uint(y) * g.grid.x + uint(x)) * kWeights[abs(dx)];
    }
    sum += row * kWeights[abs(dy)];
  }
  light[cell] = sum * g.glow.y;
}

void list(uint quad) {
  uint n = g.grid.x * g.grid.y;
  if (quad < n) {  // cleared for the next frame (the blur has read them)
    sums[quad] = 0u;
    sums[n + quad] = 0u;
  }
  uvec2 q = uvec2(quad % (g.grid.x + 1u), quad / (g.grid.x + 1u));
  bool lit = false;
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 c = min(uvec2(max(int(q.x + (k & 1u)) - 1, 0), max(int(q.y + (k >> 1)) - 1, 0)),
                  g.grid.xy - 1u);
    lit = lit || light[c.y * g.grid.x + c.x].r * g.glow.z > kVisible;
  }
  if (!lit) return;
  uint slot = atomicAdd(vertexCount, 6u) / 6u;  // the splat pass reset it
  cells[slot] = quad;
}

void main() {
  if (kPass == kGlowSplat) {
    splat();
    return;
  }
  uint i = gl_GlobalInvocationID.x;
  if (kPass == kGlowList) {
    if (i < (g.grid.x + 1u) * (g.grid.y + 1u)) list(i);
    return;
  }
  if (i < g.grid.x * g.grid.y) blur(uvec2(i % g.grid.x, i / g.grid.x), i);
}
