#version 460
// Molten rock: liquid glows from dark red at the solidus through orange to yellow at the
// eruption's temperature; solid rock is dark, with three cracks across each piece that glow
// while it is still hot and fade as it cools towards the ambient temperature. Soft-edged
// discs, premultiplied, laid over the target.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push {
  RockParams r;
};
layout(location = 0) in vec2 disc;
layout(location = 1) flat in vec3 rock;
layout(location = 0) out vec4 color;

vec3 glow(float u) {  // 0: dark red; 0.5: orange; 1: yellow
  const vec3 red = vec3(0.45, 0.04, 0.01), orange = vec3(1.0, 0.38, 0.04);
  const vec3 yellow = vec3(1.0, 0.86, 0.42);
  return u < 0.5 ? mix(red, orange, u * 2.0) : mix(orange, yellow, u * 2.0 - 1.0);
}

void main() {
  const float q = dot(disc, disc);
  if (q > 1.0) discard;
  const float alpha = 1.0 - smoothstep(0.5, 1.0, q);
  const float bulge = 1.0 - q;  // brighter at the centre: a rounded piece
  vec3 c;
  if (rock.y == 0.0 && rock.x > r.heat.x) {
    c = glow(clamp((rock.x - r.heat.x) / (r.heat.y - r.heat.x), 0.0, 1.0)) * (0.8 + 0.2 * bulge);
  } else {
    const float warm = clamp((rock.x - r.heat.z) / (r.heat.x - r.heat.z), 0.0, 1.0);
    float crack = 0.0;
    for (int k = 0; k < 3; ++k) {
      const float angle = 6.2831853 * rock.z + 2.0943951 * float(k);
      const float offset = (fract(rock.z * (7.0 + 5.0 * float(k))) - 0.5) * 0.8;
      const float d = abs(dot(disc, vec2(cos(angle), sin(angle))) - offset);
      crack = max(crack, 1.0 - smoothstep(0.02, 0.1, d));
    }
    const vec3 crust = vec3(0.085, 0.065, 0.055) * (0.7 + 0.3 * bulge);
    c = mix(crust, glow(0.6 * warm), crack * warm * warm);
  }
  color = vec4(c * alpha, alpha);
}
