#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// The fast line renderer: each alive particle walks its line x -> x + s v in screen space
// and adds its colour into a fixed-point buffer the size of the target with one atomic per
// pixel (red in the high 16 bits, green in the low 16); built with LAVA_SPLAT_PAIRS, one
// 64-bit atomic per pair of pixels one above the other where the line has both (most lines
// are steep on screen), the same sums. Software rasterisers draw lines one primitive at a
// time; this is one invocation each. With a scene depth bound, points of the line behind
// the scene are left out, as the graphics pipeline's depth test does.
#extension GL_GOOGLE_include_directive : require
#if LAVA_SPLAT_PAIRS
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif
#include "shared.h"
#include "lava_color.glsl"

layout(local_size_x_id = 0) in;

// The particles as RGBA32F texels (posAge, velMass): llvmpipe gathers texel fetches
// without the per-lane bounds-checked loop it runs for a storage-buffer load.
layout(binding = kSplatParticleBinding) uniform textureBuffer particles;
#if LAVA_SPLAT_PAIRS
layout(std430, binding = kSplatSumsBinding) restrict buffer Accumulation {
  uint64_t accumulation[];  // two pixels a word (splatIndex / 2), the even one low
};
#else
layout(std430, binding = kSplatSumsBinding) restrict buffer Accumulation {
  uint accumulation[];
};
#endif
layout(binding = kSplatDepthBinding) uniform sampler2D sceneDepth;
layout(std430, binding = kSplatMarksBinding) restrict buffer Marks {
  uint marks[];
};
layout(std430, binding = kSplatSurfaceBinding) restrict readonly buffer Nearest {
  uint nearest[];
};
layout(push_constant) uniform Push {
  SplatParams s;
};

float surfaceDepth(ivec2 q) {
  uint z = nearest[q.y * int(s.look.y) + q.x];
  return z == kSurfaceEmpty ? 0.0 : uintBitsToFloat(z);
}
#include "surface_depth.glsl"

const uint kMaxPixels = 256u;  // longer lines are cut (they are rare and off-scale anyway)

// Whether a point of the target at depth z lies behind the scene's depth there (a point off
// the target is not).
bool hidden(vec2 p, float z) {
  ivec2 at = ivec2(floor(p));
  if (any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, ivec2(s.target.xy)))) return false;
  return z > texelFetch(sceneDepth, at, 0).r;
}

// Marks the resolve's tiles that the pixels from `first` on the major axis may land in: n
// pixels along it, and across it between the first and last pixel's `minor` and a pixel
// more either side (more than the walk's rounding). Every writer writes the same 1, and a
// tile already marked is only read.
void mark(bool xMajor, int first, uint n, float minor, float slope) {
  float minorEnd = minor + float(n - 1u) * slope;
  vec2 size = vec2(s.target.xy);
  float majorSize = xMajor ? size.x : size.y, minorSize = xMajor ? size.y : size.x;
  // Clipped to the target in floats first: no int overflow far off screen.
  vec2 major = clamp(vec2(float(first), float(first) + float(n) - 1.0), 0.0, majorSize - 1.0);
  vec2 across = clamp(vec2(floor(min(minor, minorEnd)) - 1.0, floor(max(minor, minorEnd)) + 1.0),
                      0.0, minorSize - 1.0);
  uvec2 lo = uvec2(xMajor ? vec2(major.x, across.x) : vec2(across.x, major.x)) / kResolveTile;
  uvec2 hi = uvec2(xMajor ? vec2(major.y, across.y) : vec2(across.y, major.y)) / kResolveTile;
  uint tilesAcross = (s.target.x + kResolveTile - 1u) / kResolveTile;
  for (uint ty = lo.y; ty <= hi.y; ++ty)
    for (uint tx = lo.x; tx <= hi.x; ++tx) {
      uint tile = ty * tilesAcross + tx;
      if (marks[tile] == 0u) marks[tile] = 1u;
    }
}

#if LAVA_SPLAT_PAIRS
// Adds `add` to the pixel at `at` and, when `both`, to the one after it (the pixel below),
// in one atomic; takes back what a full pixel received (see below).
void addPixels(uint at, uint add, bool both) {
  bool high = (at & 1u) == 1u;
  uint64_t low = uint64_t(high ? 0u : add), upper = uint64_t(high || both ? add : 0u);
  uint64_t value = low | (upper << 32u);
  uint64_t before = atomicAdd(accumulation[at >> 1u], value);
  uint64_t back = 0ul;
  if (low != 0ul && (uint(before) >> 16) >= kSplatFull) back = low;
  if (upper != 0ul && (uint(before >> 32u) >> 16) >= kSplatFull) back |= upper << 32u;
  // Each half still holds at least what this add put there: no borrow between them.
  if (back != 0ul) atomicAdd(accumulation[at >> 1u], -back);
}
#endif

// Adds `add` to the line's n pixels from `first` along the major axis, its minor
// coordinate starting at `minor` and rising by `slope` a pixel; off the target, nothing.
void addLine(bool xMajor, int first, uint n, float minor, float slope, uint minorSize,
             float majorSize, uint add) {
#if LAVA_SPLAT_PAIRS
  for (uint k = 0u; k < n;) {
    uint major = uint(first) + k;
    uint across = uint(int(floor(minor)));  // negative wraps to huge: one unsigned test
    float next = minor + slope;
    // A steep line's pixel on an even row and its next one below, in the same column: one
    // word. (The pair lies on the target when its first pixel does: first + n is on it.)
    bool both = !xMajor && (major & 1u) == 0u && k + 1u < n && uint(int(floor(next))) == across;
    if (across < minorSize && major < uint(majorSize)) {
      uvec2 p = xMajor ? uvec2(major, across) : uvec2(across, major);
      addPixels(splatIndex(p.x, p.y, s.target.x), add, both);
    }
    minor = both ? next + slope : next;
    k += both ? 2u : 1u;
  }
#else
  for (uint k = 0u; k < n; ++k, minor += slope) {
    uint major = uint(first) + k;
    uint across = uint(int(floor(minor)));  // negative wraps to huge: one unsigned test
    if (across < minorSize && major < uint(majorSize)) {
      uvec2 p = xMajor ? uvec2(major, across) : uvec2(across, major);
      uint at = splatIndex(p.x, p.y, s.target.x);
      // A pixel full beyond any tone map is left as it is (what was added taken back): red
      // stays below 2^16 and green, never more than red in either look, below red.
      if ((atomicAdd(accumulation[at], add) >> 16) >= kSplatFull) atomicAdd(accumulation[at], -add);
    }
  }
#endif
}

void main() {
  uint i = s.range.x + gl_GlobalInvocationID.x;
  if (i >= s.target.z) return;
  Particle q = Particle(texelFetch(particles, int(2u * i)), texelFetch(particles, int(2u * i + 1u)));
  if (q.posAge.w < 0.0) return;  // not alive: draws nothing
  vec3 v = q.velMass.xyz;
  vec4 a = s.viewProj * vec4(q.posAge.xyz, 1.0);
  vec4 b = s.viewProj * vec4(q.posAge.xyz + s.style.x * v, 1.0);
  if (a.w <= 0.05 || b.w <= 0.05) return;  // behind the camera
  vec2 size = vec2(s.target.xy);
  vec2 pa = (a.xy / a.w * 0.5 + 0.5) * size;
  vec2 pb = (b.xy / b.w * 0.5 + 0.5) * size;
  if (s.target.w != 0u && hidden(pa, a.z / a.w) && hidden(pb, b.z / b.w)) return;
  if (behindSurface(pa, a.w, vec4(s.look.yzw, 0.0)) && behindSurface(pb, b.w, vec4(s.look.yzw, 0.0)))
    return;
  bool lava = s.style.w == kLookLava;
  vec2 color = lava ? lavaEmission(v, q.posAge.w, s.style) : lavaColor(v, q.posAge.w, s.style).rg;
  // Like a rasteriser's line: one pixel per pixel centre the line passes along its major
  // axis, sampled at those centres (half-open, [a, b)), so a line shorter than a pixel draws
  // nothing in the plain look, as in the graphics pipeline; the lava look draws it as one
  // pixel with the energy of its length, as the ribbon's shortest line does.
  vec2 d = pb - pa;
  bool xMajor = abs(d.x) >= abs(d.y);
  float a0 = xMajor ? pa.x : pa.y, a1 = xMajor ? pb.x : pb.y;
  float m0 = xMajor ? pa.y : pa.x, m1 = xMajor ? pb.y : pb.x;
  float majorSize = float(xMajor ? s.target.x : s.target.y);
  uint minorSize = xMajor ? s.target.y : s.target.x;
  // Clipped to the target along the major axis (in floats first: no int overflow).
  int first = int(ceil(clamp(min(a0, a1), 0.0, majorSize) - 0.5));
  int end = int(ceil(clamp(max(a0, a1), 0.0, majorSize) - 0.5));
  uint n = end > first ? min(uint(end - first), kMaxPixels) : 0u;
  float slope = n > 0u ? (m1 - m0) / (a1 - a0) : 0.0;  // a1 != a0 when a centre lies between
  float minor = m0 + (float(first) + 0.5 - a0) * slope;
  if (n == 0u) {
    if (!lava) return;
    n = 1u;  // the lava look's shortest line: one pixel where the line starts
    first = int(floor(a0));
    minor = m0;
    color *= max(length(d), 1.0);
  }
  uint add = (uint(color.r * kSplatScale + 0.5) << 16) | uint(color.g * kSplatScale + 0.5);
  if (add == 0u) return;
  mark(xMajor, first, n, minor, slope);
  addLine(xMajor, first, n, minor, slope, minorSize, majorSize, add);
}
