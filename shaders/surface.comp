#version 460
// The flow's molten surface, before it is shaded (shared.h, "The flow drawn as one molten
// surface"): four passes over surface pixels of kSurfaceScale^2 target pixels each, chosen by
// SurfaceParams.size.z. Every value a pass keeps is a minimum, a maximum or a gather in a
// fixed order: the surface is the same whatever order the device runs the particles in.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "blackbody.glsl"

layout(local_size_x_id = 0) in;

layout(std430, binding = kSurfaceParticleBinding) restrict readonly buffer Particles {
  Particle particles[];
};
layout(std430, binding = kSurfaceHeatBinding) restrict readonly buffer Heat {
  FlowHeat heat[];
};
layout(std430, binding = kSurfaceDepthBinding) restrict buffer Depth {
  uint nearest[];  // the nearest sphere's depth (clip w, m) as float bits; kSurfaceEmpty
};
layout(std430, binding = kSurfaceHottestBinding) restrict buffer Hottest {
  // Near the surface: x the hottest liquid, y the hottest solid (temperatures' float bits),
  // z the nearest liquid's depth (its float bits inverted: the largest is the nearest; 0 none)
  uvec4 hottest[];
};
layout(std430, binding = kSurfaceSmoothBinding) restrict buffer Smooth {
  SmoothPixel smoothed[];  // filtered across
};
layout(binding = kSurfaceImageBinding, rgba32f) uniform restrict writeonly image2D filtered;
layout(std430, binding = kSurfaceMarksBinding) restrict buffer Marks {
  uint marks[];  // kSurfaceTile^2 pixels a tile, row by row
};
layout(std430, binding = kSurfaceGlowBinding) restrict buffer Glow {
  uint glowSums[];  // glow.comp's cells, red then green, energy x kGlowFixed
};
layout(push_constant) uniform Push {
  SurfaceParams s;
};

bool marked(uvec2 tile) {
  return marks[tile.y * ((s.size.x + kSurfaceTile - 1u) / kSurfaceTile) + tile.x] != 0u;
}

const float kGlowFixed = 256.0;  // glow.comp's kFixed
// A sphere's footprint is cut to this radius (surface pixels): a particle nearer the camera
// than about 12 of its radii is drawn smaller than it is, and a frame's work stays bounded.
const float kMostPixels = 24.0;
// The filter's half width, at most (surface pixels).
const int kMostTaps = 6;

vec2 targetSize() {
  return vec2(s.eye.w, s.look.w);
}

// Surface pixels a metre spans at depth w (square pixels: |row 1| * height / (2 w) target
// pixels).
float pixelsPerMetre(float w) {
  float focal = length(vec3(s.viewProj[0][1], s.viewProj[1][1], s.viewProj[2][1]));
  return focal * 0.5 * s.look.w / (w * float(kSurfaceScale));
}

// Where sphere `i` falls: its centre (surface pixels), radius (surface pixels) and depth.
bool footprint(uint i, out vec2 centre, out float radius, out float w) {
  vec4 clip = s.viewProj * vec4(particles[i].posAge.xyz, 1.0);
  w = clip.w;
  centre = vec2(0.0);
  radius = 0.0;
  if (!(w > 2.0 * s.heat.w)) return false;  // behind or at the camera (NaN too)
  // Target pixel p is surface pixel p / kSurfaceScale (an odd target's last surface pixel is
  // half outside it).
  centre = (clip.xy / w * 0.5 + 0.5) * targetSize() / float(kSurfaceScale);
  radius = min(s.heat.w * pixelsPerMetre(w), kMostPixels);
  return all(greaterThan(centre + radius, vec2(0.0))) &&
         all(lessThan(centre - radius, vec2(s.size.xy)));
}

bool alive(uint i) {
  return particles[i].posAge.w >= 0.0 && heat[i].temperature > 0.0;
}

// The pixels of sphere i: their first and last (inclusive), clipped to the surface.
void pixelBox(vec2 centre, float radius, out ivec2 lo, out ivec2 hi) {
  lo = max(ivec2(floor(centre - radius)), ivec2(0));
  hi = min(ivec2(ceil(centre + radius)), ivec2(s.size.xy) - 1);
}

// The depth of sphere (centre, radius, w) at pixel p, or a negative value outside it.
float sphereDepth(ivec2 p, vec2 centre, float radius, float w) {
  vec2 d = (vec2(p) + 0.5 - centre) / radius;
  float q = dot(d, d);
  return q < 1.0 ? w - s.heat.w * sqrt(1.0 - q) : -1.0;
}

void depthPass(uint i) {
  vec2 centre;
  float radius, w;
  if (!alive(i) || !footprint(i, centre, radius, w)) return;
  ivec2 lo, hi;
  pixelBox(centre, radius, lo, hi);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      float z = sphereDepth(ivec2(x, y), centre, radius, w);
      if (z > 0.0) atomicMin(nearest[y * int(s.size.x) + x], floatBitsToUint(z));
    }
  // Every writer writes the same 1; a tile already marked is only read.
  uint across = (s.size.x + kSurfaceTile - 1u) / kSurfaceTile;
  for (uint ty = uint(lo.y) / kSurfaceTile; ty <= uint(hi.y) / kSurfaceTile; ++ty)
    for (uint tx = uint(lo.x) / kSurfaceTile; tx <= uint(hi.x) / kSurfaceTile; ++tx)
      if (marks[ty * across + tx] == 0u) marks[ty * across + tx] = 1u;
}

// The hot liquid at the surface adds its light to the glow's cells (16 target pixels a side),
// its share of the surface one rest spacing square.
void addGlow(vec2 centre, float radius, float temperature) {
  vec2 target = centre * float(kSurfaceScale);
  uvec2 cells = (uvec2(targetSize()) + kGlowCell - 1u) / kGlowCell;
  if (any(lessThan(target, vec2(0.0))) || any(greaterThanEqual(target, vec2(cells * kGlowCell))))
    return;
  float side = radius * float(kSurfaceScale) * (s.look.z / s.heat.w);
  vec2 e = blackbody(temperature).rg * (min(side * side, 4096.0) * s.look.y);
  uvec2 c = min(uvec2(target) / kGlowCell, cells - 1u);
  uint cell = c.y * cells.x + c.x;
  atomicAdd(glowSums[2u * cell], uint(e.r + 0.5));
  atomicAdd(glowSums[2u * cell + 1u], uint(e.g + 0.5));
}

void heatPass(uint i) {
  vec2 centre;
  float radius, w;
  if (!alive(i) || !footprint(i, centre, radius, w)) return;
  FlowHeat h = heat[i];
  bool solid = h.crust != 0u || h.temperature <= s.heat.x;
  uint bits = floatBitsToUint(h.temperature);
  // A layer or so behind the nearest (the ray crosses a layer of spheres one radius apart in
  // about three at the camera's usual 20 to 30 degrees): a thin crust shows what it covers.
  float band = 3.0 * s.heat.w;
  ivec2 lo, hi;
  pixelBox(centre, radius, lo, hi);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      float z = sphereDepth(ivec2(x, y), centre, radius, w);
      uint p = uint(y * int(s.size.x) + x);
      if (z <= 0.0 || z > uintBitsToFloat(nearest[p]) + band) continue;
      if (solid) {
        atomicMax(hottest[p].y, bits);
      } else {
        atomicMax(hottest[p].x, bits);
        atomicMax(hottest[p].z, ~floatBitsToUint(z));
      }
    }
  if (solid || s.look.y == 0.0) return;
  ivec2 at = clamp(ivec2(centre), ivec2(0), ivec2(s.size.xy) - 1);
  if (w - s.heat.w <= uintBitsToFloat(nearest[at.y * int(s.size.x) + at.x]) + band)
    addGlow(centre, radius, h.temperature);
}

// One surface pixel before the filter (across) or after the first (down): depth (0: empty),
// the liquid's and the solid's temperatures; whether liquid is the surface (within a quarter
// radius of the nearest), whether liquid and solid lie near it.
SmoothPixel unfiltered(ivec2 p, bool down) {
  uint k = uint(p.y) * s.size.x + uint(p.x);
  SmoothPixel o;
  if (down) {
    if (marked(uvec2(p) / kSurfaceTile)) return smoothed[k];
    o.depthHeat = vec4(0.0);  // a tile no sphere touched: across left it as it was
    o.cover = vec4(0.0);
    return o;
  }
  uint z = nearest[k];
  uvec4 t = hottest[k];
  float depth = z == kSurfaceEmpty ? 0.0 : uintBitsToFloat(z);
  bool molten = t.z != 0u && uintBitsToFloat(~t.z) <= depth + 0.25 * s.heat.w;
  o.depthHeat = vec4(depth, uintBitsToFloat(t.x), uintBitsToFloat(t.y), 0.0);
  o.cover = vec4(molten ? 1.0 : 0.0, t.x != 0u ? 1.0 : 0.0, t.y != 0u ? 1.0 : 0.0, 0.0);
  return o;
}

// A bilateral filter along one axis: neighbours weigh by distance and by how near their depth
// is to this pixel's (none beyond two radii: an edge stays an edge); empty ones not at all.
void filterPass(ivec2 p, bool down) {
  uint k = uint(p.y) * s.size.x + uint(p.x);
  SmoothPixel centre = unfiltered(p, down);
  float z0 = centre.depthHeat.x;
  SmoothPixel o;
  o.depthHeat = vec4(0.0);
  o.cover = vec4(0.0);
  if (z0 > 0.0) {
    float radius = s.heat.w * pixelsPerMetre(z0);  // a sphere, in pixels
    int taps = clamp(int(1.5 * radius + 0.5), 1, kMostTaps);
    float band = 2.0 * s.heat.w;
    ivec2 axis = down ? ivec2(0, 1) : ivec2(1, 0);
    float weights = 0.0, depth = 0.0, molten = 0.0, liquid = 0.0, solid = 0.0, tl = 0.0, ts = 0.0;
    for (int j = -taps; j <= taps; ++j) {
      ivec2 q = p + j * axis;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(s.size.xy)))) continue;
      SmoothPixel v = unfiltered(q, down);
      float dz = (v.depthHeat.x - z0) / band;
      if (v.depthHeat.x <= 0.0 || abs(dz) >= 1.0) continue;
      float r = float(j) / float(taps + 1);
      float wgt = (1.0 - r * r) * (1.0 - r * r) * (1.0 - dz * dz) * (1.0 - dz * dz);
      weights += wgt;
      depth += wgt * v.depthHeat.x;
      molten += wgt * v.cover.x;
      liquid += wgt * v.cover.y;
      solid += wgt * v.cover.z;
      tl += wgt * v.cover.y * v.depthHeat.y;
      ts += wgt * v.cover.z * v.depthHeat.z;
    }
    o.depthHeat = vec4(depth / weights, liquid > 0.0 ? tl / liquid : 0.0,
                       solid > 0.0 ? ts / solid : 0.0, 0.0);
    o.cover = vec4(molten, liquid, solid, 0.0) / weights;
  }
  if (down) {  // the image was cleared: only touched tiles are written
    imageStore(filtered, ivec2(2 * p.x, p.y), o.depthHeat);
    imageStore(filtered, ivec2(2 * p.x + 1, p.y), o.cover);
  } else {
    smoothed[k] = o;
  }
}

// The filter's passes: a workgroup a tile (gl_WorkGroupID.x), its pixels in turn; a tile no
// sphere touched is skipped whole.
void filterTile(bool down) {
  uint across = (s.size.x + kSurfaceTile - 1u) / kSurfaceTile;
  uvec2 tile = uvec2(gl_WorkGroupID.x % across, gl_WorkGroupID.x / across);
  if (!marked(tile)) return;
  for (uint i = gl_LocalInvocationIndex; i < kSurfaceTile * kSurfaceTile; i += kWorkgroupSize) {
    uvec2 p = tile * kSurfaceTile + uvec2(i % kSurfaceTile, i / kSurfaceTile);
    if (all(lessThan(p, s.size.xy))) filterPass(ivec2(p), down);
  }
}

void main() {
  uint k = gl_GlobalInvocationID.x;
  switch (s.size.z) {
    case kSurfacePassDepth:
      if (k < s.size.w) depthPass(k);
      break;
    case kSurfacePassHeat:
      if (k < s.size.w) heatPass(k);
      break;
    case kSurfacePassAcross:
      filterTile(false);
      break;
    default:
      filterTile(true);
      break;
  }
}
