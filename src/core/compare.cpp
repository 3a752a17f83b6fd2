#include "compare.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace lava {

uint32_t ulpDistance(float a, float b) {
  uint32_t ua, ub;
  std::memcpy(&ua, &a, 4);
  std::memcpy(&ub, &b, 4);
  if (ua == ub) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint32_t>::max();
  // Map the sign-magnitude bit patterns onto one monotonic integer line.
  auto ordered = [](uint32_t u) -> int64_t {
    return (u & 0x80000000u) ? -int64_t(u & 0x7fffffffu) : int64_t(u);
  };
  const int64_t d = std::llabs(ordered(ua) - ordered(ub));
  return static_cast<uint32_t>(std::min<int64_t>(d, std::numeric_limits<uint32_t>::max()));
}

Comparison compare(const std::vector<gpu::Particle>& a, const std::vector<gpu::Particle>& b) {
  Comparison c;
  c.particles = std::min(a.size(), b.size());
  for (size_t i = 0; i < c.particles; ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(gpu::Particle)) == 0) {
      ++c.equal;
      continue;
    }
    for (int k = 0; k < 4; ++k) {
      c.maxUlp = std::max({c.maxUlp, ulpDistance(a[i].posAge[k], b[i].posAge[k]),
                           ulpDistance(a[i].velMass[k], b[i].velMass[k])});
      if (k < 3) {
        c.maxDx = std::max(c.maxDx, std::fabs(a[i].posAge[k] - b[i].posAge[k]));
        c.maxDv = std::max(c.maxDv, std::fabs(a[i].velMass[k] - b[i].velMass[k]));
      }
    }
  }
  return c;
}

}  // namespace lava
