// Two particle states side by side, as `lava validate` reports them.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "lava/validation.h"

namespace lava {
namespace {

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

const float* fields(const Particle& p) {
  return &p.px;
}

}  // namespace

uint32_t ulpDistance(float a, float b) {
  const uint32_t ua = bits(a), ub = bits(b);
  if (ua == ub) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint32_t>::max();
  // Sign-magnitude patterns onto one monotonic integer line, -0 one step below +0.
  auto ordered = [](uint32_t u) -> int64_t {
    return (u & 0x80000000u) ? -int64_t(u & 0x7fffffffu) - 1 : int64_t(u);
  };
  const int64_t d = std::llabs(ordered(ua) - ordered(ub));
  return static_cast<uint32_t>(std::min<int64_t>(d, std::numeric_limits<uint32_t>::max()));
}

const char* fieldName(uint32_t field) {
  static const char* names[] = {"px",   "py",   "pz",   "age",         "vx",
                                "vy",   "vz",   "mass", "temperature", "crust"};
  return field < 10 ? names[field] : "?";
}

Comparison compare(const std::vector<Particle>& a, const std::vector<Particle>& b) {
  Comparison c;
  c.particles = std::min(a.size(), b.size());
  for (size_t i = 0; i < c.particles; ++i) {
    c.alive += b[i].age >= 0.0f;
    if (std::memcmp(&a[i], &b[i], sizeof(Particle)) == 0) {
      ++c.equal;
      continue;
    }
    const float* x = fields(a[i]);
    const float* y = fields(b[i]);
    for (uint32_t k = 0; k < 8; ++k) {
      const uint32_t ulp = ulpDistance(x[k], y[k]);
      if (ulp && !c.first) c.first = Difference{i, 0, k, bits(x[k]), bits(y[k])};
      c.maxUlp = std::max(c.maxUlp, ulp);
      const float d = std::fabs(x[k] - y[k]);
      if (k < 3) c.maxDx = std::max(c.maxDx, d);
      if (k >= 4 && k < 7) c.maxDv = std::max(c.maxDv, d);
    }
  }
  return c;
}

Comparison compare(const Scene& scene, const std::vector<Particle>& a,
                   const std::vector<Particle>& b) {
  Comparison c = compare(a, b);
  if (c.first) c.first->emitter = static_cast<uint32_t>(emitterOf(scene, c.first->particle));
  return c;
}

Comparison compare(const Scene& scene, const State& a, const State& b) {
  Comparison c = compare(a.particles, b.particles);
  const size_t n = std::min({size_t(c.particles), a.temperature.size(), b.temperature.size(),
                             a.crust.size(), b.crust.size()});
  for (size_t i = 0; i < n; ++i) {
    const uint32_t ulp = ulpDistance(a.temperature[i], b.temperature[i]);
    const bool crust = a.crust[i] != b.crust[i];
    if (ulp == 0 && !crust) continue;
    c.maxUlp = std::max(c.maxUlp, ulp);
    if (std::memcmp(&a.particles[i], &b.particles[i], sizeof(Particle)) != 0) continue;
    --c.equal;  // the particle matched: its heat is the difference
    if (!c.first || c.first->particle > i)
      c.first = ulp ? Difference{i, 0, 8, bits(a.temperature[i]), bits(b.temperature[i])}
                    : Difference{i, 0, 9, a.crust[i], b.crust[i]};
  }
  if (c.first) c.first->emitter = static_cast<uint32_t>(emitterOf(scene, c.first->particle));
  return c;
}

}  // namespace lava
