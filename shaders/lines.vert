#version 460
// Vertex pulling: vertex 2i is particle i's position x, vertex 2i+1 is x + s·v (seed eqs.
// 8-9), read straight from the buffer step.comp writes. Unborn slots fall outside the clip.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "lava_color.glsl"

layout(std430, binding = kParticleBinding) restrict readonly buffer Particles {
  Particle particles[];
};
layout(push_constant) uniform Push {
  DrawParams d;
};
layout(location = 0) out vec4 color;

void main() {
  Particle q = particles[gl_VertexIndex >> 1];
  if (q.posAge.w < 0.0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // clipped: never-emitted slots draw nothing
    color = vec4(0.0);
    return;
  }
  vec3 v = q.velMass.xyz;
  vec3 p = q.posAge.xyz + float(gl_VertexIndex & 1) * d.style.x * v;
  gl_Position = d.viewProj * vec4(p, 1.0);
  color = vec4(lavaColor(v, q.posAge.w, d.style), 1.0);
}
