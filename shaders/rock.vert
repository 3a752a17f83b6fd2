#version 460
// The flow as molten rock: instance i is flow slot i, a disc facing the camera (two triangles)
// read straight from the flow's own particles and heat (flow.comp's). One draw lays the solid
// rock (crust and cinders), the next the liquid over it, so that hot rock shows wherever it
// lies over crust. Unborn slots, and those of the other phase, draw nothing.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "clip.glsl"

layout(std430, binding = kRockParticleBinding) readonly buffer Particles {
  Particle particles[];
};
layout(std430, binding = kRockHeatBinding) readonly buffer Heat {
  FlowHeat heat[];
};
layout(push_constant) uniform Push {
  RockParams r;
};
layout(location = 0) out vec2 disc;       // -1..1 across the disc
layout(location = 1) flat out vec3 rock;  // x temperature (K), y 1 for crust, z a hash in [0, 1)

const vec2 kCorners[6] =
    vec2[](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, -1.0), vec2(1.0, 1.0),
           vec2(-1.0, 1.0));

void main() {
  const uint i = gl_InstanceIndex;
  const Particle q = particles[i];
  const FlowHeat h = heat[i];
  const bool solid = h.crust != 0u || h.temperature <= r.heat.x;
  if (q.posAge.w < 0.0 || solid != (r.draw.x == kRockSolid)) {
    gl_Position = kNowhere;
    disc = vec2(0.0);
    rock = vec3(0.0);
    return;
  }
  // The view's right and up in the world are its first two rows (a rigid view under a
  // symmetric projection), and the clip w row points away from the camera: the disc is
  // brought a radius towards it, so that the ground and the cone cut no rock resting on them.
  const vec3 right = normalize(vec3(r.viewProj[0][0], r.viewProj[1][0], r.viewProj[2][0]));
  const vec3 up = normalize(vec3(r.viewProj[0][1], r.viewProj[1][1], r.viewProj[2][1]));
  const vec3 toward = -normalize(vec3(r.viewProj[0][3], r.viewProj[1][3], r.viewProj[2][3]));
  const vec2 corner = kCorners[gl_VertexIndex];
  const vec3 x = q.posAge.xyz + r.heat.w * (toward + corner.x * right + corner.y * up);
  gl_Position = r.viewProj * vec4(x, 1.0);
  disc = corner;
  rock = vec3(h.temperature, h.crust != 0u ? 1.0 : 0.0, float(hashMix(i) >> 8u) / 16777216.0);
}
