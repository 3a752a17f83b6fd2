// Clipping in the vertex shader, so that every vertex a draw emits lies in the view volume (-w <=
// x, y <= w, 0 <= z <= w). The lines are the same (up to the rounding of a clipped end, as the
// rasteriser's own clipping would round it), but a software rasteriser (llvmpipe) sends every chunk
// of a draw holding one vertex outside through its slow per-primitive clipping path, at a cost that
// grows with the draw's size.

// Where a primitive that draws nothing puts all its vertices: a zero-length line or a
// zero-area triangle (no fragments on any rasteriser), inside the volume, on a pixel corner.
const vec4 kNowhere = vec4(-1.0, -1.0, 0.5, 1.0);

// Narrows [t0, t1] to where the signed distance, da at a and db at b, is not negative.
void clipToPlane(float da, float db, inout float t0, inout float t1) {
  if (da < 0.0 && db < 0.0) {
    t1 = -1.0;  // wholly outside
  } else if (da < 0.0) {
    t0 = max(t0, da / (da - db));
  } else if (db < 0.0) {
    t1 = min(t1, da / (da - db));
  }
}

// End `end` (0: a, 1: b) of the segment a -> b (clip space) clipped to the view volume, or
// kNowhere when none of it is inside. Both ends' invocations compute the same t0 and t1; a
// segment wholly inside returns a or b exactly.
vec4 clipLineEnd(vec4 a, vec4 b, uint end) {
  float t0 = 0.0, t1 = 1.0;
  clipToPlane(a.w + a.x, b.w + b.x, t0, t1);
  clipToPlane(a.w - a.x, b.w - b.x, t0, t1);
  clipToPlane(a.w + a.y, b.w + b.y, t0, t1);
  clipToPlane(a.w - a.y, b.w - b.y, t0, t1);
  clipToPlane(a.z, b.z, t0, t1);
  clipToPlane(a.w - a.z, b.w - b.z, t0, t1);
  if (t0 >= t1) return kNowhere;
  float t = end == 0u ? t0 : t1;
  if (t == 0.0) return a;
  if (t == 1.0) return b;
  // On the boundary up to rounding: clamped so that it cannot fall just outside.
  vec4 p = mix(a, b, t);
  return vec4(clamp(p.xy, vec2(-p.w), vec2(p.w)), clamp(p.z, 0.0, p.w), p.w);
}
