// The GPU/CPU contract: particle layout, dispatch parameters, workgroup size and the
// stateless random hash. Included by C++ (src/) and by GLSL (shaders/*.comp, *.vert).
#ifndef LAVA_SHARED_H
#define LAVA_SHARED_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>

#include "lava/state.h"
namespace lava::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
#define LAVA_FN inline
#else
#define LAVA_FN
#endif

// Invocations per compute workgroup of every compute shader.
const uint kWorkgroupSize = 64u;
// Particles one step.comp invocation advances, interleaved (its main() spells out four).
const uint kParticlesPerInvocation = 4u;
// Descriptor bindings of the simulation and drawing pipelines.
const uint kParticleBinding = 0u;
const uint kScheduleBinding = 1u;
// The same particles read as RGBA32F texels (posAge, velMass): on llvmpipe a texel fetch
// is a branch-free gather, a storage-buffer load a bounds-checked loop over the lanes.
const uint kParticleTexelBinding = 2u;
// Bindings of splat.comp (particles as texels, the sums), resolve.frag and copy.comp.
const uint kSplatParticleBinding = 0u;
const uint kSplatSumsBinding = 1u;
const uint kResolveSumsBinding = 0u;
const uint kCopySourceBinding = 0u;
const uint kCopyDestinationBinding = 1u;
// ground.vert: the plane's two triangles, then the crater cone's side quads.
const uint kCraterSides = 48u;
const uint kGroundVertices = 6u + 6u * kCraterSides;
// Random-stream components drawn per emitted particle: 3 for velocity, then disc tries.
const uint kVelocityComponents = 3u;
// Rejection-sampling tries for the emitter disc; all failing has odds (1-pi/4)^16 < 2e-11
// and places the particle at the centre. Rejection keeps sin/cos/sqrt (not bit-exact
// across drivers) out of the emission.
const uint kDiscTries = 16u;
// Tangential speed (m/s) below which a bouncing particle's x or z velocity becomes 0.
const float kRestSpeed = 1e-4f;

// One particle, 32 bytes in std430. Unborn slots have posAge.w < 0. C++ names the same
// floats px py pz age vx vy vz mass (lava::Particle).
#ifdef __cplusplus
using Particle = ::lava::Particle;
#else
struct Particle {
  vec4 posAge;   // xyz position (m), w age since emission (s); < 0: never emitted
  vec4 velMass;  // xyz velocity (m/s), w mass (kg)
};
#endif

// One step's emission, written by the host (ring-buffer bookkeeping stays on the host).
struct EmitEntry {
  uvec4 ring;  // x first slot (head), y slots born this step, z serial low, w serial high
  uvec4 sums;  // x particles emitted before this step since the plan began (mod 2^32)
};

// Push constants of step.comp: the scene plus which steps and particles to run.
struct StepParams {
  vec4 emitter;   // xyz emitter centre (m), w disc radius (m)
  vec4 velocity;  // xyz mean launch velocity (m/s), w step size h (s)
  vec4 spread;    // xyz launch velocity spread (m/s), w gravity g (m/s^2)
  vec4 wind;      // xyz wind force (N), w linear drag (N s/m)
  vec4 material;  // x restitution, y tangential retention, z mass (kg), w unused
  uvec4 run;      // x seed, y capacity, z first schedule entry, w steps in this dispatch
  uvec4 chunk;    // x first particle of the bound range, y particles in it
};

// Push constants of lines.vert / ground.vert: camera and line style.
struct DrawParams {
  mat4 viewProj;  // world (m) to Vulkan clip space
  vec4 style;     // x line scale s (s), y speed (m/s) at which a line is fully red,
                  // z age (s) at which it has cooled to its darkest, w unused
  vec4 crater;    // xyz emitter centre (m), w emitter radius (m)
};

// Push constants of splat.comp and resolve.frag, the fast line renderer.
struct SplatParams {
  mat4 viewProj;  // as DrawParams
  vec4 style;     // as DrawParams
  uvec4 target;   // x width, y height (pixels), z particles in the bound range
};
// Fixed-point scale of one line's color in the accumulation buffer (red in the high 16
// bits, green in the low 16): about a thousand lines can overlap before green overflows.
const float kSplatScale = 48.0f;

// lowbias32 (C. Wellons): a stateless 32-bit integer mix with good avalanche.
LAVA_FN uint hashMix(uint x) {
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// 32 random bits for (seed, 64-bit serial, component): the same on every device.
LAVA_FN uint randomBits(uint seed, uint serialLo, uint serialHi, uint component) {
  return hashMix(hashMix(hashMix(hashMix(seed) ^ serialLo) ^ serialHi) ^ component);
}

// Uniform in [-1, 1) on a 2^-23 grid; every operation is exact in float32.
LAVA_FN float signedUnit(uint bits) {
  return float(int(bits >> 8u) - 8388608) * (1.0f / 8388608.0f);
}

#ifdef __cplusplus
static_assert(sizeof(Particle) == 32 && offsetof(Particle, age) == 12 &&
                  offsetof(Particle, vx) == 16 && offsetof(Particle, mass) == 28,
              "Particle must match std430 (posAge, velMass)");
static_assert(sizeof(EmitEntry) == 32, "EmitEntry must match std430 (two uvec4)");
static_assert(sizeof(StepParams) == 112, "StepParams must fit 128 bytes of push constants");
static_assert(offsetof(StepParams, run) == 80, "StepParams members must stay vec4-aligned");
static_assert(sizeof(DrawParams) == 96, "DrawParams must fit 128 bytes of push constants");
static_assert(sizeof(SplatParams) == 96, "SplatParams must fit 128 bytes of push constants");
}  // namespace lava::gpu
#endif
#undef LAVA_FN
#endif
