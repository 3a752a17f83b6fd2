#version 460
// The flow's molten surface, shaded (docs/flow.md, "On screen"): surface.comp's filtered
// depth made a surface again, its normal from its neighbours, its depth the scene's depth test
// sees. Liquid glows by its temperature (blackbody.glsl); crust is dark rough rock with its own
// dull glow while hot, cracked, and its cracks glow with the liquid beneath or beside it. The
// energy is tone mapped as the lines' is.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "blackbody.glsl"
#include "lava_color.glsl"

layout(binding = kSurfaceDrawBinding, rgba32f) uniform restrict readonly image2D filtered;
layout(push_constant) uniform Push {
  SurfaceParams s;
};
layout(location = 0) out vec4 color;

const float kCrackCell = 0.2;    // m: the crust's plates
const float kCrackWidth = 0.08;  // of a plate: F2 - F1 below it is a crack
const vec3 kRock = vec3(0.035, 0.03, 0.026);  // crust's colour energy under the night sky

// Pixel q's depth (0: empty).
float depthAt(ivec2 q) {
  q = clamp(q, ivec2(0), ivec2(s.size.xy) - 1);
  return imageLoad(filtered, ivec2(2 * q.x, q.y)).x;
}

// The camera's basis: right, up (as the projection's rows point) and forward, and the
// focal lengths across and down.
struct Basis {
  vec3 right, up, forward;
  vec2 focal;
};
Basis basis() {
  Basis b;
  vec3 r = vec3(s.viewProj[0][0], s.viewProj[1][0], s.viewProj[2][0]);
  vec3 u = vec3(s.viewProj[0][1], s.viewProj[1][1], s.viewProj[2][1]);
  b.focal = vec2(length(r), length(u));
  b.right = r / b.focal.x;
  b.up = u / b.focal.y;
  b.forward = vec3(s.viewProj[0][3], s.viewProj[1][3], s.viewProj[2][3]);
  return b;
}

// Where surface pixel coordinate `at` (fractional, in surface pixels: target pixels over
// kSurfaceScale) at depth z lies, in the camera's basis.
vec3 viewPoint(vec2 at, float z, Basis b) {
  vec2 ndc = at * float(kSurfaceScale) / vec2(s.eye.w, s.look.w) * 2.0 - 1.0;
  return vec3(ndc * z / b.focal, z);
}

// The normal of the surface at pixel q, in the camera's basis, facing the camera: of the
// two neighbours along each axis, the one at the nearer depth (an edge takes no slope from
// what lies behind it).
vec3 normalAt(ivec2 q, float z, Basis b) {
  vec3 centre = viewPoint(vec2(q) + 0.5, z, b);
  vec3 side[2];
  for (int axis = 0; axis < 2; ++axis) {
    ivec2 step = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
    float zp = depthAt(q + step), zm = depthAt(q - step);
    bool plus = zp > 0.0 && (zm <= 0.0 || abs(zp - z) <= abs(zm - z));
    float zn = plus ? zp : (zm > 0.0 ? zm : z);
    vec3 n = viewPoint(vec2(q + (plus ? step : -step)) + 0.5, zn, b);
    side[axis] = plus ? n - centre : centre - n;
  }
  vec3 normal = normalize(cross(side[0], side[1]));
  return dot(normal, centre) > 0.0 ? -normal : normal;
}

// 0 on the crust's cracks, 1 in its plates: the edges of a Voronoi pattern over the ground,
// blurred over `pixel` (a pixel's size, in plates): a crack narrower than a pixel shows as
// the share of the pixel it covers, not as a whole pixel or none.
float plates(vec2 x, float pixel) {
  vec2 u = x / kCrackCell;
  ivec2 base = ivec2(floor(u));
  float first = 9.0, second = 9.0;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      ivec2 c = base + ivec2(i, j);
      uint h = hashMix(uint(c.x) * 73856093u ^ uint(c.y) * 19349663u);
      vec2 site = vec2(c) + vec2(h & 0xffffu, h >> 16u) * (1.0 / 65536.0);
      float d = distance(u, site);
      second = d < first ? first : min(second, d);
      first = min(first, d);
    }
  return smoothstep(-pixel, pixel, second - first - kCrackWidth);
}

void main() {
  ivec2 q = min(ivec2(gl_FragCoord.xy) / int(kSurfaceScale), ivec2(s.size.xy) - 1);
  SmoothPixel p;
  p.depthHeat = imageLoad(filtered, ivec2(2 * q.x, q.y));
  float z = p.depthHeat.x;
  if (z <= 0.0) discard;
  p.cover = imageLoad(filtered, ivec2(2 * q.x + 1, q.y));
  Basis b = basis();
  vec3 v = viewPoint(gl_FragCoord.xy / float(kSurfaceScale), z, b);
  vec3 world = s.eye.xyz + v.x * b.right + v.y * b.up + v.z * b.forward;
  vec4 clip = s.viewProj * vec4(world, 1.0);
  gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);
  vec3 n = normalAt(q, z, b);
  vec3 normal = n.x * b.right + n.y * b.up + n.z * b.forward;
  float facing = max(dot(n, -normalize(v)), 0.0);

  float crusted = smoothstep(0.35, 0.65, 1.0 - p.cover.x);
  float liquid = p.cover.y;  // under a thin crust, or beside it
  float tl = p.depthHeat.y, ts = p.depthHeat.z;
  // Liquid: its own light, dimmer where the surface turns from the camera (a cooler skin).
  vec3 molten = blackbody(tl) * (0.55 + 0.45 * facing);
  // Crust: rough dark rock lit by the sky from above, glowing dully while hot; its cracks
  // show the heat beneath it (the liquid's, where there is liquid under or beside it).
  uint grain = hashMix(uint(int(floor(world.x * 60.0))) * 73856093u ^
                       uint(int(floor(world.z * 60.0))) * 19349663u ^
                       uint(int(floor(world.y * 60.0))) * 83492791u);
  float rough = 0.75 + 0.5 * float(grain >> 24u) / 255.0;
  vec3 rock = kRock * rough * (0.35 + 0.65 * max(normal.y, 0.0)) + 0.2 * blackbody(ts);
  float beneath = liquid > 0.0 ? mix(ts, tl, min(1.0, 2.0 * liquid)) : ts;
  float pixel = z * float(kSurfaceScale) / (b.focal.y * 0.5 * s.look.w);  // a surface pixel (m)
  vec3 crust = mix(blackbody(beneath) * 1.2, rock, plates(world.xz, pixel / kCrackCell));
  vec3 energy = mix(molten, crust, crusted) * s.look.x;
  color = vec4(lavaToneMap(energy), 1.0);
}
