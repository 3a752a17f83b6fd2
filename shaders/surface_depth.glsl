// Whether a point at depth w (clip w, m) at target pixel p lies behind the flow's surface
// (of kSurfaceScale^2 pixels a surface pixel) by more than surface.z; surface: x, y the
// surface's pixels across and down (0: no surface). The including shader defines
// surfaceDepth(q): surface pixel q's depth (clip w, m), or 0 where there is no surface.
bool behindSurface(vec2 p, float w, vec4 surface) {
  if (surface.x == 0.0) return false;
  ivec2 q = ivec2(floor(p)) / int(kSurfaceScale);
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(surface.xy)))) return false;
  float z = surfaceDepth(q);
  return z > 0.0 && w > z + surface.z;
}
