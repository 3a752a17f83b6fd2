// The color of a lava line: orange when slow, red when fast (seed §5), darker as it cools.
// style: x line scale (s), y speed (m/s) of full red, z age (s) of the darkest.
const vec3 kOrange = vec3(1.0, 0.55, 0.08);
const vec3 kRed = vec3(0.95, 0.06, 0.02);

vec3 lavaColor(vec3 velocity, float age, vec4 style) {
  float hot = clamp(length(velocity) / style.y, 0.0, 1.0);
  float cooling = clamp(age / style.z, 0.0, 1.0);
  return mix(kOrange, kRed, hot) * mix(1.0, 0.3, cooling);
}
