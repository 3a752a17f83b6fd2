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
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
#define LAVA_FN inline
#define LAVA_PRECISE
#else
#define LAVA_FN
#define LAVA_PRECISE precise
#endif

// Invocations per compute workgroup of every compute shader.
const uint kWorkgroupSize = 64u;
// Particles one step.comp invocation advances, interleaved: its main() is written for four.
const uint kParticlesPerInvocation = 4u;
// Descriptor bindings of the simulation and drawing pipelines.
const uint kParticleBinding = 0u;
const uint kScheduleBinding = 1u;
// The same particles read as RGBA32F texels (posAge, velMass): on llvmpipe a texel fetch
// is a branch-free gather, a storage-buffer load a bounds-checked loop over the lanes.
const uint kParticleTexelBinding = 2u;
const uint kSceneBinding = 3u;  // SceneParams, one copy per frame slot
// Bindings of splat.comp (particles as texels, the sums), resolve.frag and copy.comp.
const uint kSplatParticleBinding = 0u;
const uint kSplatSumsBinding = 1u;
const uint kResolveSumsBinding = 0u;
const uint kCopySourceBinding = 0u;
const uint kCopyDestinationBinding = 1u;
// The solids ground.vert generates from gl_VertexIndex, one draw each (BackdropParams.solid.w).
const uint kSolidGround = 0u;  // two triangles, 24 m across
const uint kSolidCone = 1u;    // kRoundSides side quads and a top cap fan
const uint kSolidSphere = 2u;  // kRoundSides x kSphereRings quads
const uint kSolidBox = 3u;     // 12 triangles
const uint kSolidPlane = 4u;   // a square of 8 m in the plane
const uint kRoundSides = 48u;
const uint kSphereRings = 24u;
const uint kGroundVertices = 6u;
const uint kConeVertices = 6u * kRoundSides + 3u * kRoundSides;
const uint kSphereVertices = 6u * kRoundSides * kSphereRings;
const uint kBoxVertices = 36u;
const uint kPlaneVertices = 6u;
// The lava look's sky (sky.vert): one band below the haze's edge, then kSkyBands - 1 up to the
// top, each coloured at its edges (within 0.3 of a display step of the gradient with 17).
const uint kSkyBands = 17u;
const uint kSkyVertices = 6u * kSkyBands;

// Specialization constants of step.comp (0 is the workgroup size): which modules the
// scene uses, so that the default scene pays for none of the others.
const uint kIntegratorConstant = 1u;  // kExplicitEuler ...
const uint kEmittersConstant = 2u;    // 1..kMaxEmitters
const uint kForcesConstant = 3u;      // 0..kMaxForces
const uint kCollidersConstant = 4u;   // 0..kMaxColliders
const uint kLifetimesConstant = 5u;   // 1 when some emitter has a lifetime
// The kind of each force (bit i: 1 for a vortex) and collider (bits 2i, 2i+1: kPlane ...
// kCone): each slot's code is then known when the pipeline is built, so a device that runs
// both sides of a branch (a CPU device's SIMD lanes) runs only the kind in that slot.
const uint kForceKindsConstant = 6u;
const uint kColliderKindsConstant = 7u;
// 0 for the dispatches of the workgroups none of whose particles is born in the dispatch
// (the host knows which: births fill each emitter's ring contiguously): their invocations
// leave out the birth search and the emission, which a CPU device's SIMD lanes would run
// masked for every particle of every dispatch, born or not.
const uint kBirthsConstant = 8u;
// Bit k set when emitter k is a flow emitter: step.comp leaves its particles to flow.comp.
const uint kFlowEmittersConstant = 9u;

const uint kMaxEmitters = 16u;
const uint kMaxForces = 16u;
const uint kMaxColliders = 16u;
// The values of lava::Shape, Integrator, ForceType and ColliderType.
const uint kShapePoint = 0u;
const uint kShapeDisc = 1u;
const uint kShapeSphere = 2u;
const uint kShapeBox = 3u;
const uint kExplicitEuler = 0u;
const uint kSemiImplicitEuler = 1u;
const uint kVelocityVerlet = 2u;
const uint kAttractor = 0u;
const uint kVortex = 1u;
const uint kPlane = 0u;
const uint kSphere = 1u;
const uint kBox = 2u;
const uint kCone = 3u;

// Random-stream components drawn per emitted particle: 3 for velocity, then the shape's.
const uint kVelocityComponents = 3u;
// Rejection-sampling tries for the disc (2 draws each) and the sphere (3 each): all
// failing has odds below 2e-11 (disc) and 1e-10 (sphere) and places the particle at the
// centre. Rejection keeps sin/cos/sqrt (not exact across drivers) out of the emission.
const uint kDiscTries = 16u;
const uint kSphereTries = 32u;
// Tangential speed (m/s) below which a bounce's tangential velocity becomes 0 (static
// friction).
const float kRestSpeed = 1e-4f;
// Velocity components below this (2^-24 m/s) become +0 after emission, the integrator and
// each collider response: no denormal ever enters the state.
const float kTinySpeed = 5.9604644775390625e-8;
// Rounds of the ground and the colliders that contact runs at most (docs/model.md
// "Contact"): a particle still inside a solid after them takes back its start of step.
const uint kContactRounds = 4u;
// Below this squared distance from its axis a point counts as on a cone's axis.
const float kAxisSquared = 1e-30f;
// The bit pattern whose halving subtraction starts the cone's 1/sqrt (then Newton steps).
const uint kRsqrtMagic = 0x5f3759dfu;

// One particle, 32 bytes in std430. Unborn slots have posAge.w < 0. C++ names the same
// floats px py pz age vx vy vz mass (lava::Particle).
#ifdef __cplusplus
using Particle = ::lava::Particle;
#else
struct Particle {
  vec4 posAge;   // xyz position (m), w age since emission (s); < 0: not alive
  vec4 velMass;  // xyz velocity (m/s), w mass (kg)
};
#endif

// One step's births of one emitter, written by the host (ring bookkeeping stays there).
struct EmitEntry {
  uvec4 ring;  // x first slot born (in the emitter's ring), y slots born, z serial low, w high
  uvec4 sums;  // x births before this step since the dispatch's first step (mod 2^32)
};

// An emitter and the constants the host derives from it (float32, docs/model.md).
struct EmitterParams {
  vec4 position;   // xyz centre (m), w radius (m)
  vec4 velocity;   // xyz mean launch velocity (m/s), w mass (kg)
  vec4 spread;     // xyz launch velocity spread (m/s), w lifetime (s; 0: none)
  vec4 size;       // xyz box half-extents (m), w hm = h / m
  vec4 constants;  // x hh = (0.5 h) hm, y hk = 0.5 hm, z w = wind.y - m g (N), w unused
  uvec4 ring;      // x shape, y seed + k, z capacity, w first slot of the ring in the state
};

struct ForceParams {
  vec4 position;  // xyz point (m), w strength k
  vec4 axis;      // xyz vortex axis, w attractor radius^2 (m^2)
  uvec4 kind;     // x kAttractor or kVortex, y 1 when the attractor acts everywhere
};

struct ColliderParams {
  vec4 position;  // xyz plane point, sphere or box centre, cone base centre (m)
  vec4 shape;     // plane: xyz unit normal; sphere: x radius, y radius^2; box: xyz
                  // half-extents; cone: x base radius, y (top - base) / height, z height
  vec4 cone;      // cone: x, y the side normal's radial and vertical parts, z the cap's y
                  // (base + height + margin), w margin (m)
  vec4 material;  // x restitution, y friction
  uvec4 kind;     // x kPlane, kSphere, kBox or kCone
};

// The scene as step.comp reads it (a uniform buffer; every member a vec4 multiple, so
// std140 and C++ agree).
struct SceneParams {
  vec4 world;  // x h (s), y ground restitution, z ground friction, w drag (N s/m)
  vec4 wind;   // xyz wind (N), w unused
  EmitterParams emitters[kMaxEmitters];
  ForceParams forces[kMaxForces];
  ColliderParams colliders[kMaxColliders];
};

// Push constants of step.comp: which steps and which particles one dispatch runs.
struct StepParams {
  uvec4 run;    // x first schedule entry, y steps, z entries per emitter in the schedule
  uvec4 chunk;  // x first particle (state index) of the bound chunk, y particles in it,
               // z the dispatch's first invocation (a multiple of kWorkgroupSize)
};

// flow.comp (docs/model.md, "The flow"): its bindings (the schedule and the scene as
// step.comp's), its passes over each step, and what they read and write. The flow's slots are
// numbered 0.. in state order (its emitters' rings one after another): the flow index.
const uint kFlowParticleBinding = 0u;  // Particle per flow index: the flow's own copy
const uint kFlowHeatBinding = 2u;      // FlowHeat per flow index
const uint kFlowParamsBinding = 4u;    // FlowParams
const uint kFlowNextBinding = 5u;      // FlowNext per flow index: the step's results
const uint kFlowScratchBinding = 6u;   // FlowScratch per flow index
const uint kFlowGridBinding = 7u;      // uint: counts[buckets], start[buckets + 1], sorted[slots],
                                       // then per run of buckets its count and its start
const uint kFlowBirths = 0u;       // per flow slot: the step's births; cell, bucket, counts
const uint kFlowScan = 1u;         // one workgroup: each block's start; block counts to 0
const uint kFlowBlockStarts = 2u;  // per block of runs: their starts; run counts to 0
const uint kFlowStarts = 3u;       // per run of buckets: their starts; counts to 0
const uint kFlowScatter = 4u;      // per flow slot: into its bucket (in any order)
const uint kFlowOrder = 5u;        // per bucket: its lowest slots first, in order; count to 0
const uint kFlowDensity = 6u;      // per flow slot: the first neighbour pass
const uint kFlowForces = 7u;       // per flow slot: the second neighbour pass and the step
const uint kFlowStore = 8u;        // per flow slot: the results over the state
const uint kFlowPasses = 9u;
// Buckets per run: the scan sums runs, then each run's buckets get their starts in parallel
// (the buckets are a power of two, 1024 or more).
const uint kFlowRun = 32u;
// Runs per block: the scan's one workgroup sums blocks of 32 runs (1,024 buckets), whose
// runs then get their starts at once, then the runs' buckets theirs.
const uint kFlowBlock = 32u;
// The most slots of one bucket that the flow's neighbour loops read: its lowest flow
// indices, in order (docs/model.md "Neighbours"). A settled flow holds about 8 to a cell, so
// the cap binds only where particles pile up (a point burst, clamped far positions), and
// keeps a step's work linear in the particles there.
const uint kFlowBucketCap = 64u;
const uint kFlowUnsorted = 0xffffffffu;  // FlowScratch.cell.w of a slot not in the grid
// Entries of the viscosity table, solidus to temperature.
const uint kViscosityEntries = 64u;

struct FlowHeat {
  float temperature;  // K; 0 in unborn slots
  uint crust;         // 1: crust
};

struct FlowNext {
  vec4 posAge;
  vec4 velMass;
  vec4 heat;  // x temperature, y 1 for crust
};

struct FlowScratch {
  ivec4 cell;   // xyz the cell, w its bucket (kFlowUnsorted: not in the grid)
  vec4 rates;   // x pi = c^2 max(theta - 1, 0) / theta^2, y the viscous and z the conductive
                // exchange's stability factors, w 1 when a solid particle touches crust
  vec4 own;     // x the viscosity at the step's start; yzw its emitter's density, pressure
                // and Laplacian weights: what its neighbours read of it, looked up once
};

// How a flow emitter places its births (FlowEmitterParams::lattice.x; flow/lattice.h).
const uint kFillRandom = 0u;  // emit(): the emitter's shape at random, launched
const uint kFillBox = 1u;     // at rest on the lattice inside a box
const uint kFillBall = 2u;    // at rest on the lattice inside a sphere or disc

struct FlowEmitterParams {
  vec4 weights;  // x density, y pressure (1/m), z laplacian (s/m^2), w birth temperature (K)
  uvec4 slots;   // x the emitter, y its first flow index, z its first state slot, w capacity
  uvec4 lattice;  // x kFill*; box: y, z, w sites along x, y, z; ball: y the largest
                  // i^2 + j^2 + k^2, z its integer root, w the layers each side (disc: 0)
  vec4 spacing;   // x the lattice's spacing (m); box: y, z, w its centre in sites
};

// The flow's constants (flow/flow.h's FlowConstants), one copy per frame slot.
struct FlowParams {
  vec4 kernel;  // x 1 / radius, y 1 / radius^2, z touch distance^2, w c^2 (m^2/s^2)
  vec4 heat;    // x solidus, y temperature, z ambient (K), w the table's scale (1/K)
  vec4 rates;   // x viscosity, y viscosity at the solidus (m^2/s), z h cooling-air,
                // w h (cooling-air + cooling-ground)
  vec4 contact; // x 2 conduction (m^2/s), y restitution
  vec4 limits;  // x the pair cut, y the tiny term, z the coincident distance^2, w cell limit
  uvec4 sizes;  // x buckets (a power of two), y flow slots, z flow emitters
  vec4 table[kViscosityEntries / 4u];
  FlowEmitterParams emitters[kMaxEmitters];
};

// Push constants of flow.comp.
struct FlowStepParams {
  uvec4 run;  // x the step's schedule entry, y the pass, z entries per emitter in the schedule
};

// The flow drawn as one molten surface (surface.comp, surface.vert / surface.frag), at one
// surface pixel per kSurfaceScale x kSurfaceScale pixels of the target. surface.comp's passes:
// - depth: each alive flow slot a sphere; each surface pixel keeps the nearest depth (clip w,
//   its float bits' atomicMin: the same on any order), and the tiles it touches are marked;
// - heat: the spheres within three radii behind a pixel's nearest keep the hottest liquid
//   and the hottest solid there, and the nearest liquid (atomicMax of their bits); the hot
//   liquid at the surface adds its light to the glow's cells;
// - across, down: a bilateral filter of the depth (neighbours at other depths weigh
//   nothing, so edges stay sharp) and of the heat, across then down.
// surface.frag shades the result over the host's target, depth-tested against its depth.
const uint kSurfaceScale = 2u;
const uint kSurfaceParticleBinding = 0u;  // the flow's particles (GpuSimulation::flowBuffers)
const uint kSurfaceHeatBinding = 1u;      // FlowHeat beside each
const uint kSurfaceDepthBinding = 2u;     // uint a surface pixel: the nearest depth's bits
const uint kSurfaceHottestBinding = 3u;   // uvec4 a surface pixel: hottest liquid and solid
const uint kSurfaceSmoothBinding = 4u;    // SmoothPixel a surface pixel: filtered across
const uint kSurfaceGlowBinding = 5u;      // the glow's sums (glow.comp's kGlowSumsBinding)
// The filtered surface, an RGBA32F storage image two texels a surface pixel (its
// SmoothPixel: depthHeat at x = 2i, cover at 2i + 1): written by the down pass, read by the
// draws (on lavapipe a fragment shader's storage-buffer loads slow the whole pass down
// several times over; an image's do not).
const uint kSurfaceImageBinding = 6u;
// The tiles of kSurfaceTile^2 surface pixels that any sphere touches (a uint each, row by
// row, non-zero when touched): surface.vert draws those only.
const uint kSurfaceTile = 32u;
const uint kSurfaceMarksBinding = 7u;
const uint kSurfaceDrawBinding = 0u;       // surface.frag: the filtered surface
const uint kSurfaceDrawMarksBinding = 1u;  // surface.vert: the tiles
// surface.comp's passes (SurfaceParams.size.z).
const uint kSurfacePassDepth = 0u;
const uint kSurfacePassHeat = 1u;
const uint kSurfacePassAcross = 2u;
const uint kSurfacePassDown = 3u;
const uint kSurfaceEmpty = 0xffffffffu;  // a surface pixel no sphere covers

// A filtered surface pixel: x depth (clip w, m; 0 where empty), y the liquid's temperature,
// z the solid's (K), w unused; cover: x the share where liquid is the surface, y where liquid
// lies near it (at it or under a thin crust), z where solid does.
struct SmoothPixel {
  vec4 depthHeat;
  vec4 cover;
};

// Push constants of surface.comp, surface.vert and surface.frag.
struct SurfaceParams {
  mat4 viewProj;  // as DrawParams
  vec4 heat;      // x solidus, y the eruption's temperature, z ambient (K), w sphere radius (m)
  vec4 look;      // x exposure, y the glow's energy scale (0: no glow), z the rest spacing (m),
                  // w the target's height (pixels)
  vec4 eye;       // xyz the camera (m), w the target's width (pixels)
  uvec4 size;     // x, y surface pixels across and down, z the pass, w flow slots
};

// The two looks (DrawParams.style.w, BackdropParams.eye.w).
const float kLookPlain = 0.0;  // the lab handout's: orange to red by speed, darker with age, added
const float kLookLava = 1.0;   // molten rock: energy tone mapped as it is added, and glow

// Push constants of lines.vert: camera and line style.
struct DrawParams {
  mat4 viewProj;  // world (m) to Vulkan clip space
  vec4 style;     // x line scale s (s), y speed (m/s) at which a line is fully red,
                  // z age (s) over which it cools, w the look
  vec4 target;    // x width, y height (pixels), z exposure, w shortest line drawn (px)
  vec4 surface;   // the flow's surface, which hides lines behind it: x, y its pixels across
                  // and down (0: no surface), z how far behind it a line is hidden (m)
};
// lines.frag: the filtered surface (surface.comp's kSurfaceImageBinding).
const uint kLineSurfaceBinding = 1u;

// Push constants of ground.vert / ground.frag: one solid of the backdrop.
struct BackdropParams {
  mat4 viewProj;  // as DrawParams
  vec4 solid;     // xyz where the solid is (plane point, centre, cone base centre) (m),
                  // w kSolidGround ... kSolidPlane
  vec4 size;      // cone: x base radius, y top radius, z height; sphere: x radius; box: xyz
                  // half-extents; plane: xyz unit normal (m)
  vec4 vent;      // xyz the main vent (emitter 0) (m), w its radius: where the rock glows
  vec4 eye;       // xyz the camera (m): a plane is seen from its normal's side only; w the
                  // look (kLookPlain, kLookLava)
};

// Push constants of splat.comp and resolve.frag, the fast line renderer.
struct SplatParams {
  mat4 viewProj;  // as DrawParams
  vec4 style;     // as DrawParams
  uvec4 target;   // x width, y height (pixels), z the end of the dispatch's particles in the
                  // bound chunk, w 1 when a scene depth is bound to test against
  vec4 look;      // x exposure; yzw the flow's surface, as DrawParams.surface
  uvec4 range;    // x the first of the dispatch's particles in the bound chunk
};
// Fixed-point scale of one line's colour (lava: energy) in the splat's sums: red in the high
// 16 bits, green in the low 16, each at most 1.7 a line (lava: red 1.64, green 1.0). A
// pixel's red stops at kSplatFull (energy 390, far past where either look saturates: the
// 64 adds that may race past it still fit), and green, never more than red, below it.
const float kSplatScale = 128.0f;
const uint kSplatFull = 50000u;
// The sums are laid out in blocks of 2 x 8 pixels, one 64-byte cache line each, a column after
// another (splatIndex): a line's next pixels often share its block, and the cores of a CPU device,
// which add into the same sums, pass fewer cache lines between them. Tall blocks suit the lines,
// which are mostly steep on screen (falling lava); 1 x 16 would cost shallow lines more.
// Two pixels one above the other, the upper on an
// even row, are one 8-byte word: where the device has 64-bit atomics, one add covers both
// (splat.comp, LAVA_SPLAT_PAIRS). The buffer covers the target rounded up to whole blocks.
const uint kSplatBlockWidth = 2u;
const uint kSplatBlockHeight = 8u;
LAVA_FN uint splatIndex(uint x, uint y, uint width) {
  uint blocksAcross = (width + kSplatBlockWidth - 1u) / kSplatBlockWidth;
  return ((y / kSplatBlockHeight) * blocksAcross + x / kSplatBlockWidth) *
             (kSplatBlockWidth * kSplatBlockHeight) +
         (x % kSplatBlockWidth) * kSplatBlockHeight + y % kSplatBlockHeight;
}
const uint kSplatDepthBinding = 2u;  // the scene's depth, sampled (when target.w = 1)
// The resolve draws only the tiles of kResolveTile^2 pixels that lines were added into:
// splat.comp marks them (one uint per tile, row by row, non-zero when marked) and
// resolve.vert makes one quad of each marked tile. On a CPU device a full-screen resolve
// costs as much as a frame of a few thousand particles.
const uint kResolveTile = 64u;
const uint kSplatMarksBinding = 3u;
const uint kSplatSurfaceBinding = 4u;  // the flow's surface's nearest depths (SplatParams.look)
const uint kResolveMarksBinding = 1u;

// The lava look's glow: bright lines spread light over cells of kGlowCell^2 pixels (glow.comp
// adds each line's energy into its cell, then blurs the cells and lists where there is light,
// a tile of kGlowTile^2 quads per workgroup), drawn as quads over the lit cells only
// (glow.vert, glow.frag).
const uint kGlowCell = 16u;
const uint kGlowTile = 16u;
const uint kGlowParticlesBinding = 0u;  // glow.comp: the particles as texels
const uint kGlowSumsBinding = 1u;       // the cells' energy, red then green a cell (uint)
const uint kGlowLightBinding = 2u;      // after the blur: RG float per cell
const uint kGlowListBinding = 3u;       // the quads to draw, and the draw's arguments
const uint kGlowSumTexelsBinding = 4u;  // the sums again, R32G32_UINT texels (light pass)
const uint kGlowMarksBinding = 5u;      // the splat's marked resolve tiles (when folded, below)
const uint kGlowDrawListBinding = 0u;   // glow.vert: the list
const uint kGlowDrawLightBinding = 1u;  // glow.vert: the light, R32G32_SFLOAT texels or buffer
const uint kGlowDrawSumsBinding = 2u;   // glow_resolve.frag: the splat's sums
struct GlowParams {
  mat4 viewProj;  // as DrawParams
  vec4 style;     // as DrawParams
  uvec4 grid;     // x cells across, y cells down, z the end of the dispatch's particles in
                  // the bound chunk, w stride: every stride-th particle from target.w is
                  // added, its energy times stride
  uvec4 target;   // x width, y height (pixels), z 1 for the first dispatch's splat, w the
                  // first of the dispatch's particles in the bound chunk
  vec4 glow;      // x threshold (energy per pixel below which nothing glows), y strength,
                  // z exposure
};

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
  LAVA_PRECISE float u = float(int(bits >> 8u) - 8388608) * (1.0f / 8388608.0f);
  return u;
}

#ifdef __cplusplus
static_assert(sizeof(Particle) == 32 && offsetof(Particle, age) == 12 &&
                  offsetof(Particle, vx) == 16 && offsetof(Particle, mass) == 28,
              "Particle must match std430 (posAge, velMass)");
static_assert(sizeof(EmitEntry) == 32, "EmitEntry must match std430 (two uvec4)");
static_assert(sizeof(EmitterParams) == 96 && sizeof(ForceParams) == 48 &&
                  sizeof(ColliderParams) == 80,
              "scene parameters are whole vec4s (std140 array strides)");
static_assert(sizeof(SceneParams) == 32 + 16 * (96 + 48 + 80), "SceneParams as std140 lays it out");
static_assert(offsetof(SceneParams, forces) == 32 + 16 * 96, "SceneParams members stay vec4s");
static_assert(sizeof(FlowHeat) == 8 && sizeof(FlowNext) == 48 && sizeof(FlowScratch) == 48,
              "the flow's per-slot records match std430");
static_assert(sizeof(FlowParams) == 96 + 16 * 16 + 64 * kMaxEmitters,
              "FlowParams as std140 lays it out");
static_assert(sizeof(StepParams) == 32, "StepParams fits any push-constant budget");
static_assert(sizeof(SurfaceParams) == 128, "SurfaceParams must fit 128 bytes of push constants");
static_assert(sizeof(SmoothPixel) == 32, "SmoothPixel matches std430");
static_assert(sizeof(DrawParams) == 112, "DrawParams must fit 128 bytes of push constants");
static_assert(sizeof(GlowParams) == 128, "GlowParams must fit 128 bytes of push constants");
static_assert(sizeof(BackdropParams) == 128, "BackdropParams must fit 128 bytes of push constants");
static_assert(sizeof(SplatParams) == 128, "SplatParams must fit 128 bytes of push constants");
}  // namespace lava::gpu
#endif
#undef LAVA_FN
#undef LAVA_PRECISE
#endif
