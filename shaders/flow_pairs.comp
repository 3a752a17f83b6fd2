#version 460
// The ceiling of `lava bench --flow`: the flow's density sum over neighbour lists made
// beforehand (contiguous, no grid, no sort, no second pass): the neighbour loop alone. Timed,
// not compared: inversesqrt stands for flow.comp's bit-exact 1/sqrt.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) restrict readonly buffer Positions {
  vec4 positions[];
};
layout(std430, binding = 1) restrict readonly buffer Starts {
  uint starts[];  // particle i's neighbours are lists[starts[i] .. starts[i + 1])
};
layout(std430, binding = 2) restrict readonly buffer Lists {
  uint lists[];
};
layout(std430, binding = 3) restrict writeonly buffer Sums {
  float sums[];
};
layout(push_constant) uniform Push {
  uvec4 count;  // x particles
  vec4 kernel;  // x 1 / radius
};

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= count.x) return;
  const vec3 x = positions[i].xyz;
  float theta = 0.0;
  const uint end = starts[i + 1u];
  for (uint e = starts[i]; e < end; ++e) {
    const vec3 d = x - positions[lists[e]].xyz;
    const float q = dot(d, d);
    const float r = q * inversesqrt(max(q, 1e-30));
    const float t = max(1.0 - r * kernel.x, 0.0);
    theta += t * t * t;
  }
  sums[i] = theta;
}
