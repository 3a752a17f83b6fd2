#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// Vertex pulling: vertex 2i is particle i's position x, vertex 2i+1 is x + s·v (the handout's
// lines), read straight from the buffer step.comp writes, the line clipped to the view volume here
// (clip.glsl). Unborn slots draw nothing. The buffer is read through its texel view (two RGBA32F
// texels a particle): on llvmpipe a gather, where a storage-buffer load is a loop over the lanes.
// The lava look stretches a line shorter than the
// shortest drawn (d.target.w pixels) to it, keeping the energy of its true length, so that lava at
// rest stays visible, and gives it its tone-mapped colour (lava_color.glsl).
#extension GL_GOOGLE_include_directive : require
#include "shared.h"
#include "clip.glsl"
#include "lava_color.glsl"

layout(binding = kParticleBinding) uniform textureBuffer particles;  // two texels a particle
layout(push_constant) uniform Push {
  DrawParams d;
};
layout(location = 0) out vec4 color;

void main() {
  int i = gl_VertexIndex >> 1;
  Particle q = Particle(texelFetch(particles, 2 * i), texelFetch(particles, 2 * i + 1));
  if (q.posAge.w < 0.0) {
    gl_Position = kNowhere;  // never-emitted slots draw nothing
    color = vec4(0.0);
    return;
  }
  vec3 v = q.velMass.xyz;
  uint end = uint(gl_VertexIndex & 1);
  vec4 a = d.viewProj * vec4(q.posAge.xyz, 1.0);
  vec4 b = d.viewProj * vec4(q.posAge.xyz + d.style.x * v, 1.0);
  if (d.style.w != kLookLava) {
    gl_Position = clipLineEnd(a, b, end);
    color = vec4(lavaColor(v, q.posAge.w, d.style), 1.0);
    return;
  }
  float energy = 1.0;
  if (a.w > 0.0 && b.w > 0.0) {
    vec2 half_ = d.target.xy * 0.5;
    vec2 along = (b.xy / b.w - a.xy / a.w) * half_;  // pixels
    float length_ = sqrt(dot(along, along));
    if (length_ < d.target.w) {  // stretched along its direction (or across the screen)
      vec2 dir = length_ > 1e-4 ? along / length_ : vec2(1.0, 0.0);
      vec2 tip = a.xy / a.w + dir * (d.target.w / half_);
      b = vec4(tip * b.w, b.z, b.w);
      energy = max(length_, 1.0) / d.target.w;
    }
  }
  gl_Position = clipLineEnd(a, b, end);
  vec3 e = lavaEnergy(lavaEmission(v, q.posAge.w, d.style)) * (energy * d.target.z);
  color = vec4(lavaToneMap(e), 1.0);
}
