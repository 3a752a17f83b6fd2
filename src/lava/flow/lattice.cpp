// A flow emitter's lattice fill: see lattice.h. Built with -ffp-contract=off like the model.
#include "lattice.h"

#include <cmath>
#include <string>

#include "lava/error.h"

namespace lava::detail {
namespace {

// Sites along one axis or radius beyond which a lattice is refused: its site search stays a
// short loop, and its count far below 2^32.
constexpr double kMostAcross = 4096.0;

// floor(sqrt(m)) digit by digit in integers, as flow.comp computes it: no float operation.
uint32_t integerRoot(uint32_t m) {
  uint32_t root = 0, bit = 1u << 30;
  while (bit > m) bit >>= 2;
  for (; bit != 0; bit >>= 2) {
    if (m >= root + bit) {
      m -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
  }
  return root;
}

// The sites of a ball's row (j, k): 2 w + 1, w the row's half-width; 0 outside.
uint32_t rowSites(const gpu::uvec4& s, int32_t j, int32_t k) {
  const int64_t rest = int64_t(s.y) - int64_t(j) * j - int64_t(k) * k;
  return rest < 0 ? 0u : 2u * integerRoot(uint32_t(rest)) + 1u;
}

}  // namespace

Lattice flowLattice(const Scene& scene, size_t emitter) {
  const Emitter& e = scene.emitters[emitter];
  Lattice l;
  if (e.fill != Fill::Lattice || !scene.flow) return l;
  const double d = std::cbrt(double(e.mass) / double(scene.flow->density));
  const std::string at = "emitter[" + std::to_string(emitter) + "].fill";
  l.spacing.x = float(d);
  if (e.shape == Shape::Box) {
    l.shape.x = gpu::kFillBox;
    const float half[3] = {e.size.x, e.size.y, e.size.z};
    uint32_t* n[3] = {&l.shape.y, &l.shape.z, &l.shape.w};
    float* centre[3] = {&l.spacing.y, &l.spacing.z, &l.spacing.w};
    l.sites = 1;
    for (int a = 0; a < 3; ++a) {
      // As many spacings as fit across (the cells of the sites inside the box), at least one;
      // a size within float32's rounding of a whole number of spacings takes it whole.
      const double across = std::floor(2.0 * double(half[a]) / d * (1.0 + 1e-6));
      if (across > kMostAcross)
        throw InvalidArgument(at, "the box is " + std::to_string(uint64_t(across)) +
                                      " spacings across; at most 4096 per axis");
      *n[a] = std::max(1u, uint32_t(across));
      *centre[a] = float(0.5 * double(*n[a] - 1));
      l.sites *= *n[a];
    }
    return l;
  }
  if (e.shape != Shape::Sphere && e.shape != Shape::Disc)
    throw InvalidArgument(at, "\"lattice\" fills a box, sphere or disc; emitter[" +
                                  std::to_string(emitter) + "].shape is " + name(e.shape));
  const double q = double(e.radius) / d;
  if (q > kMostAcross)
    throw InvalidArgument(
        at, "the radius is " + std::to_string(uint64_t(q)) + " spacings; at most 4096");
  l.shape.x = gpu::kFillBall;
  l.shape.y = uint32_t(std::floor(q * q * (1.0 + 1e-6)));
  l.shape.z = integerRoot(l.shape.y);
  l.shape.w = e.shape == Shape::Sphere ? l.shape.z : 0u;
  const int32_t k = int32_t(l.shape.z), layers = int32_t(l.shape.w);
  for (int32_t y = -layers; y <= layers; ++y)
    for (int32_t z = -k; z <= k; ++z) l.sites += rowSites(l.shape, y, z);
  return l;
}

void latticeSite(const Lattice& l, uint32_t index, int32_t o[3]) {
  const gpu::uvec4& s = l.shape;
  if (s.x == gpu::kFillBox) {
    o[0] = int32_t(index % s.y);
    o[2] = int32_t((index / s.y) % s.w);
    o[1] = int32_t(index / (s.y * s.w));
    return;
  }
  const int32_t k = int32_t(s.z), layers = int32_t(s.w);
  uint32_t rest = index;
  for (int32_t y = -layers; y <= layers; ++y)
    for (int32_t z = -k; z <= k; ++z) {
      const uint32_t row = rowSites(s, y, z);
      if (rest < row) {
        o[0] = int32_t(rest) - int32_t(row / 2);
        o[1] = y;
        o[2] = z;
        return;
      }
      rest -= row;
    }
  o[0] = o[1] = o[2] = 0;  // past the last site: not reached for index < sites
}

Vec3 latticePosition(const Lattice& l, const Vec3& position, uint32_t index) {
  int32_t o[3];
  latticeSite(l, index, o);
  const float d = l.spacing.x;
  const bool box = l.shape.x == gpu::kFillBox;
  const float c[3] = {box ? l.spacing.y : 0.0f, box ? l.spacing.z : 0.0f, box ? l.spacing.w : 0.0f};
  return {position.x + d * (float(o[0]) - c[0]), position.y + d * (float(o[1]) - c[1]),
          position.z + d * (float(o[2]) - c[2])};
}

}  // namespace lava::detail
