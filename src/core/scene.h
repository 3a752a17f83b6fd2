// The scene of SPEC §2: every simulation parameter with its default (seed values where
// the seed gives one), and its translation into the shader's push constants.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>

#include "shared.h"

namespace lava {

struct Scene {
  uint32_t particles = 5000;             // ring-buffer capacity
  double rate = 1000.0;                  // emission rate (1/s)
  float dt = 0.001f;                     // step h (s)
  float gravity = 9.81f;                 // g (m/s^2)
  float restitution = 0.45f;             // epsilon in [0, 1]
  float friction = 0.7f;                 // tangential retention alpha in [0, 1]
  float lineScale = 0.04f;               // s: line from x to x + s v
  glm::vec3 emitter{0.0f, 0.6f, 0.0f};   // crater mouth centre (m)
  float emitterRadius = 0.15f;           // crater mouth radius (m)
  glm::vec3 velocity{0.0f, 6.0f, 0.0f};  // mean launch velocity (m/s)
  glm::vec3 spread{1.6f, 1.5f, 1.6f};    // per-component launch spread (m/s)
  float mass = 1.0f;                     // m (kg)
  glm::vec3 wind{0.0f, 0.0f, 0.0f};      // wind force (N)
  float drag = 0.0f;                     // linear drag (N s/m)
  uint32_t seed = 20170101u;             // RNG seed
};

// Steps of size scene.dt in `seconds` of simulated time (rounded).
uint64_t stepsIn(const Scene& scene, double seconds);

// Push constants for one dispatch; the caller fills run.zw and chunk.
gpu::StepParams stepParams(const Scene& scene);

}  // namespace lava
