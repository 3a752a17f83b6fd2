#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// The lava look's glow, at one cell per kGlowCell x kGlowCell pixels, in two passes (two
// modules: glow_splat without LAVA_GLOW_LIGHT, glow_light with it), over sums the renderer
// cleared:
// - splat: every stride-th alive particle adds its line's energy (times the stride) into
//   the cell of the line's middle, in fixed point (a pair of uint a cell, red and green);
// - light: per workgroup, a tile of kGlowTile x kGlowTile quads of the dual grid (one more
//   across and down than cells: a quad spans four neighbouring cells' centres, the edges
//   clamped). Each cell's energy per pixel above the threshold (the brightest channel less
//   the threshold, the hue kept: only what glows brightly spreads), blurred over 5 x 5 cells
//   (separably, in shared memory) and times the strength, is the light the cell receives;
//   the tile's quads where any of the four has visible light are appended to the list (its
//   vertex count 6 per quad). When the draw also resolves the splat's sums (specialization
//   constant 1), the quads over the tiles splat.comp marked are listed too, lit or not.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(local_size_x_id = 0) in;

layout(binding = kGlowParticlesBinding) uniform textureBuffer particles;
layout(std430, binding = kGlowSumsBinding) restrict buffer Sums {
  uint sums[];  // per cell its red, then its green
};
layout(std430, binding = kGlowLightBinding) restrict writeonly buffer Light {
  vec2 light[];
};
layout(std430, binding = kGlowListBinding) restrict buffer List {
  uint vertexCount;  // VkDrawIndirectCommand
  uint instanceCount;
  uint firstVertex;
  uint firstInstance;
  uint quads[];  // the quads to draw
};
#if LAVA_GLOW_TEXELS
layout(binding = kGlowSumTexelsBinding) uniform utextureBuffer sumTexels;  // the sums again, RG
#endif
#if LAVA_GLOW_LIGHT
layout(constant_id = 1) const bool kResolves = false;
layout(std430, binding = kGlowMarksBinding) restrict readonly buffer Marks {
  uint marks[];  // splat.comp's resolve tiles, row by row, non-zero when marked
};
#endif
layout(push_constant) uniform Push {
  GlowParams g;
};

const float kFixed = 256.0;  // sums: energy x kFixed
const float kVisible = 0.002;  // glow energy below this adds less than half a display step
// A 5-tap Gaussian (sigma 1 cell), normalised.
const int kTaps = 3;
const float kWeights[kTaps] = float[](0.4026, 0.2442, 0.0545);

void splat() {
  if (gl_GlobalInvocationID.x == 0u && g.target.z == 1u) {  // the first chunk's first
    vertexCount = 0u;  // the list's draw arguments: no vertices yet, one instance
    instanceCount = 1u;
    firstVertex = 0u;
    firstInstance = 0u;
  }
  uint i = g.target.w + gl_GlobalInvocationID.x * g.grid.w;
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
  atomicAdd(sums[2u * cell], uint(e.r + 0.5));
  atomicAdd(sums[2u * cell + 1u], uint(e.g + 0.5));
}

// The light pass's blocks, in cells from the tile's first quad less one (the cells its
// quads span) and less the blur's reach on either side.
const int kTile = int(kGlowTile);
const int kReach = kTaps - 1;
const int kCells = kTile + 1;             // cells whose light the tile's quads read
const int kSpan = kCells + 2 * kReach;    // cells whose energy their blur reads
shared vec2 energy[kSpan * kSpan];        // thresholded, 0 off the grid
shared vec2 rows[kSpan * kCells];         // blurred across
shared float visible[kCells * kCells];    // red light times exposure
shared uint anyEnergy;

bool onGrid(ivec2 c) {
  return all(greaterThanEqual(c, ivec2(0))) && all(lessThan(c, ivec2(g.grid.xy)));
}

vec2 thresholded(ivec2 c) {
  if (!onGrid(c)) return vec2(0.0);
  // Read as texels, a cell's two sums in one: on llvmpipe a gather, where a storage-buffer
  // load is a loop over lanes; these fetches are most of the light pass's cost there. Built
  // without LAVA_GLOW_TEXELS (where a texel view cannot hold the cells), from the buffer.
  int cell = c.y * int(g.grid.x) + c.x;
#if LAVA_GLOW_TEXELS
  uvec2 fixedPoint = texelFetch(sumTexels, cell).rg;
#else
  uvec2 fixedPoint = uvec2(sums[2 * cell], sums[2 * cell + 1]);
#endif
  vec2 e = vec2(fixedPoint) * (1.0 / (kFixed * float(kGlowCell * kGlowCell)));
  float peak = max(e.r, e.g);
  return peak > g.glow.x ? e * ((peak - g.glow.x) / peak) : vec2(0.0);
}

#if LAVA_GLOW_LIGHT
// Whether splat.comp marked a resolve tile under quad q's pixels (glow.vert's placement:
// from the centre of cell q - 1 to that of cell q, clipped to the target).
bool marked(ivec2 q) {
  ivec2 size = ivec2(g.target.xy);
  ivec2 lo = clamp(q * int(kGlowCell) - int(kGlowCell / 2u), ivec2(0), size);
  ivec2 hi = clamp(q * int(kGlowCell) + int(kGlowCell / 2u), ivec2(0), size);  // exclusive
  if (any(greaterThanEqual(lo, hi))) return false;
  uvec2 t0 = uvec2(lo) / kResolveTile, t1 = uvec2(hi - 1) / kResolveTile;
  uint tilesAcross = (g.target.x + kResolveTile - 1u) / kResolveTile;
  bool hit = false;
  for (uint ty = t0.y; ty <= t1.y; ++ty)
    for (uint tx = t0.x; tx <= t1.x; ++tx) hit = hit || marks[ty * tilesAcross + tx] != 0u;
  return hit;
}

void lightTile() {
  uint lane = gl_LocalInvocationIndex;
  ivec2 first = ivec2(gl_WorkGroupID.xy) * kTile - 1;  // the block's first cell
  if (lane == 0u) anyEnergy = 0u;
  barrier();
  for (uint k = lane; k < uint(kSpan * kSpan); k += kWorkgroupSize) {
    vec2 e = thresholded(first - kReach + ivec2(int(k) % kSpan, int(k) / kSpan));
    energy[k] = e;
    if (any(greaterThan(e, vec2(0.0)))) atomicOr(anyEnergy, 1u);
  }
  barrier();
  bool dark = anyEnergy == 0u;  // the same in the whole workgroup
  if (dark) {  // nothing reaches the tile: no light; only marked quads to list, if any
    for (uint k = lane; k < kGlowTile * kGlowTile; k += kWorkgroupSize) {
      ivec2 c = first + 1 + ivec2(int(k) % kTile, int(k) / kTile);
      if (onGrid(c)) light[c.y * int(g.grid.x) + c.x] = vec2(0.0);
    }
    if (!kResolves) return;
  } else {
    for (uint k = lane; k < uint(kSpan * kCells); k += kWorkgroupSize) {
      int x = int(k) % kCells, y = int(k) / kCells;
      vec2 row = vec2(0.0);
      for (int dx = -kReach; dx <= kReach; ++dx)
        row += energy[y * kSpan + x + kReach + dx] * kWeights[abs(dx)];
      rows[k] = row;
    }
    barrier();
    for (uint k = lane; k < uint(kCells * kCells); k += kWorkgroupSize) {
      ivec2 b = ivec2(int(k) % kCells, int(k) / kCells);
      vec2 sum = vec2(0.0);
      for (int dy = -kReach; dy <= kReach; ++dy)
        sum += rows[(b.y + kReach + dy) * kCells + b.x] * kWeights[abs(dy)];
      vec2 l = sum * g.glow.y;
      visible[k] = l.r * g.glow.z;
      ivec2 c = first + b;
      if (b.x > 0 && b.y > 0 && onGrid(c)) light[c.y * int(g.grid.x) + c.x] = l;  // the tile's own
    }
    barrier();
  }
  for (uint k = lane; k < kGlowTile * kGlowTile; k += kWorkgroupSize) {
    ivec2 q = ivec2(gl_WorkGroupID.xy) * kTile + ivec2(int(k) % kTile, int(k) / kTile);
    if (any(greaterThan(q, ivec2(g.grid.xy)))) continue;
    bool lit = false;
    for (int j = 0; j < 4 && !dark; ++j) {  // the four cells whose centres are the quad's corners
      ivec2 c = clamp(q + ivec2(j & 1, j >> 1) - 1, ivec2(0), ivec2(g.grid.xy) - 1);
      ivec2 b = c - first;
      lit = lit || visible[b.y * kCells + b.x] > kVisible;
    }
    if (!lit && !(kResolves && marked(q))) continue;
    uint slot = atomicAdd(vertexCount, 6u) / 6u;  // recordPrepare's fills reset it
    quads[slot] = uint(q.y) * (g.grid.x + 1u) + uint(q.x);
  }
}

#endif

void main() {
#if LAVA_GLOW_LIGHT
  lightTile();
#else
  splat();
#endif
}
