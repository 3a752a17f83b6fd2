// The backdrop's stone (ground.vert, ground.frag): each solid's colour, the light from the
// sky it receives, and the ground's grid lines.
const vec3 kGridLine = vec3(0.03);  // added on the ground's 1 m grid lines

vec3 solidAlbedo(uint kind) {
  return kind == kSolidGround ? vec3(0.075, 0.065, 0.06)
       : kind == kSolidCone   ? vec3(0.16, 0.12, 0.10)
                              : vec3(0.20, 0.19, 0.18);
}

float skyLight(vec3 n) {
  return 0.35 + 0.65 * max(dot(n, normalize(vec3(0.3, 1.0, 0.2))), 0.0);
}

// 1 on the ground's grid lines (world x or z within 0.015 m of a whole metre), else 0.
float onGridLine(vec3 world) {
  vec2 cell = abs(fract(world.xz) - 0.5);
  return step(0.485, max(cell.x, cell.y));
}
