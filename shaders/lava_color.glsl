// The colour of a lava line. style: x line scale (s), y speed (m/s) of full red, z age (s) of the
// darkest, w the look. Both looks: orange when slow, red when fast (the handout's rule), darker as
// it cools.
const vec3 kOrange = vec3(1.0, 0.55, 0.08);
const vec3 kRed = vec3(0.95, 0.06, 0.02);

// The plain look: the lab handout's solid colours, added (and clipped) in an 8-bit target.
vec3 lavaColor(vec3 velocity, float age, vec4 style) {
  float hot = clamp(length(velocity) / style.y, 0.0, 1.0);
  float cooling = clamp(age / style.z, 0.0, 1.0);
  return mix(kOrange, kRed, hot) * mix(1.0, 0.3, cooling);
}

// The lava look's energy of a line per pixel of its length, red and green: fresh lava is
// hot and yellow, cooling over style.z seconds through orange (slow) or red (fast) to a
// dark crust that stays faintly visible.
vec2 lavaEmission(vec3 velocity, float age, vec4 style) {
  float fast = clamp(length(velocity) / style.y, 0.0, 1.0);
  vec2 hue = mix(vec2(1.0, 0.42), vec2(1.0, 0.16), fast);       // orange slow, red fast
  float heat = exp(-max(age, 0.0) * (3.0 / style.z));           // 1 at birth, 5% at style.z
  hue = mix(hue, vec2(1.0, 0.6), smoothstep(0.6, 1.0, heat));   // yellow-hot when fresh
  float crust = 0.06 + 0.08 * (1.0 - fast);                     // cooled rock glows dimly
  return hue * (crust + 1.5 * heat * heat);
}

// Energy (red, green) to colour energy: blue follows from them, the same for every pass
// (yellow-white lava gains a little, red lava none).
vec3 lavaEnergy(vec2 rg) {
  return vec3(rg, rg.r > 0.0 ? 0.15 * rg.g * rg.g / rg.r : 0.0);
}

// The lava look's tone map, per channel: T(x) ~ 1 - exp(-x), as (1 + x/16)^-16 (four
// squarings and a division, cheap on every device). The targets hold T of the energy added
// so far and lines are blended src (1 - dst) + dst, which keeps them at T of the sum: the
// energy is unbounded, the colour never clips, and bright lava turns yellow, not white.
vec3 lavaToneMap(vec3 x) {
  vec3 g = 1.0 + max(x, vec3(0.0)) * (1.0 / 16.0);
  g *= g;
  g *= g;
  g *= g;
  g *= g;
  return 1.0 - 1.0 / g;
}

// x^(1/2.2), the display's encoding, for x in [0, 1], within 0.17 of a display step: a
// polynomial in x^(1/4) (two square roots; a pow is a log2 and an exp2 a channel, and the
// backdrop, drawn each frame while the camera moves, encodes every pixel).
vec3 displayEncode(vec3 x) {
  vec3 q = sqrt(sqrt(max(x, vec3(0.0))));
  return q * (0.0402006 + q * (1.2038502 + q * (-0.3550050 + q * 0.1112770)));
}

// One pixel of splat.comp's sums (fixed point, red in the high 16 bits, green in the low 16)
// as the red and green the lines added there.
vec2 splatSums(uint sum) {
  return vec2(float(sum >> 16) / kSplatScale, float(sum & 0xFFFFu) / kSplatScale);
}

// The lava look's colour of one pixel of the splat's sums at `exposure`: resolve.frag's and
// glow_resolve.frag's.
vec3 lavaSplatColor(uint sum, float exposure) {
  return lavaToneMap(lavaEnergy(splatSums(sum)) * exposure);
}
