#version 460
// The glow, interpolated between cell centres, for the blend src (1 - dst) + dst.
layout(location = 0) in vec3 color;
layout(location = 0) out vec4 outColor;

void main() {
  outColor = vec4(color, 1.0);
}
