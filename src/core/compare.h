// GPU-vs-CPU comparison of two particle states, as `lava validate` reports it.
#pragma once
#include <cstdint>
#include <vector>

#include "shared.h"

namespace lava {

// Distance in units in the last place between two floats (0 when bitwise equal; the
// largest value when exactly one is NaN).
uint32_t ulpDistance(float a, float b);

struct Comparison {
  uint64_t particles = 0;  // slots compared
  uint64_t equal = 0;      // slots bitwise identical (all 8 floats)
  float maxDx = 0.0f;      // largest |Δ| of a position component (m)
  float maxDv = 0.0f;      // largest |Δ| of a velocity component (m/s)
  uint32_t maxUlp = 0;     // largest ULP distance of any float in the slot
};

Comparison compare(const std::vector<gpu::Particle>& a, const std::vector<gpu::Particle>& b);

}  // namespace lava
