#version 460
// The roofline reference for `lava bench`: moves exactly the bytes one unfused step moves
// (two vec4 read and two written per particle), with the same workgroup size and chunking.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = kCopySourceBinding) restrict readonly buffer Source {
  Particle source[];
};
layout(std430, binding = kCopyDestinationBinding) restrict writeonly buffer Destination {
  Particle destination[];
};
layout(push_constant) uniform Push {
  uvec4 chunk;  // x first particle of the bound range (unused here), y particles in it
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < chunk.y) {
    destination[i] = source[i];
  }
}
