#version 460
#extension GL_EXT_samplerless_texture_functions : require  // texelFetch on texel views
// One dispatch advances every particle of the bound chunk by run.y steps of the model
// (docs/model.md): emission (from the host's per-emitter ring schedule), forces, the integrator,
// the ground, the colliders, lifetimes. Particles are independent, so each invocation keeps its
// particles in registers across the steps.
//
// Exactness: every float variable of the state path is `precise` (its operations carry
// NoContraction: no FMA, no reassociation), dot products and cross products are written out
// in the order docs/model.md gives, quotients and products of scene constants come from the host,
// and the only square root and division are the sphere collider's. The execution modes ask
// for IEEE round-to-nearest-even and preserved signed zeros where the device offers them.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_spirv_intrinsics : require
#include "shared.h"

#if LAVA_SIGNED_ZERO
spirv_execution_mode(capabilities = [4466], 4461, 32);  // SignedZeroInfNanPreserve 32
#endif
#if LAVA_RTE
spirv_execution_mode(capabilities = [4467], 4462, 32);  // RoundingModeRTE 32
#endif

layout(local_size_x_id = 0) in;
layout(constant_id = kIntegratorConstant) const uint kIntegrator = kExplicitEuler;
layout(constant_id = kEmittersConstant) const uint kEmitters = 1u;
layout(constant_id = kForcesConstant) const uint kForces = 0u;
layout(constant_id = kCollidersConstant) const uint kColliders = 0u;
layout(constant_id = kLifetimesConstant) const uint kLifetimes = 0u;
layout(constant_id = kForceKindsConstant) const uint kForceKinds = 0u;
layout(constant_id = kColliderKindsConstant) const uint kColliderKinds = 0u;
layout(constant_id = kBirthsConstant) const uint kBirths = 1u;
layout(constant_id = kFlowEmittersConstant) const uint kFlowEmitters = 0u;

layout(std430, binding = kParticleBinding) writeonly buffer Particles {
  Particle particles[];
};
layout(binding = kParticleTexelBinding) uniform textureBuffer particleTexels;  // same memory
layout(std430, binding = kScheduleBinding) restrict readonly buffer Schedule {
  EmitEntry schedule[];
};
layout(std140, binding = kSceneBinding) uniform Scene {
  SceneParams scene;
};
layout(push_constant) uniform Push {
  StepParams p;
};

// What a particle's steps need of its emitter, read once per dispatch.
struct Model {
  float hm;        // h / m
  float hh;        // (0.5 h) hm
  float hk;        // 0.5 hm
  float w;         // wind.y - m g
  float lifetime;  // s; 0: none
};

Model model(uint k) {
  const EmitterParams e = scene.emitters[k];
  return Model(e.size.w, e.constants.x, e.constants.y, e.constants.z, e.spread.w);
}

#include "model.glsl"

// One step of an alive particle (after any birth).
void step(const World g, const Model e, inout precise vec3 x, inout precise vec3 v,
          inout precise float age) {
  const precise vec3 x0 = x;
  precise float h = g.h;
  precise float hm = e.hm;
  precise float w = e.w;
  precise vec3 f;
  force(g, x, v, w, f);
  if (kIntegrator == kSemiImplicitEuler) {
    precise vec3 v1 = v + hm * f;
    x = x + h * v1;
    v = v1;
  } else if (kIntegrator == kVelocityVerlet) {
    precise vec3 x1 = (x + h * v) + e.hh * f;
    precise vec3 vs = v + hm * f;
    precise vec3 f1;
    force(g, x1, vs, w, f1);
    v = v + e.hk * (f + f1);
    x = x1;
  } else {  // explicit Euler (the lab handout's): position with the start-of-step velocity
    precise vec3 x1 = x + h * v;
    v = v + hm * f;
    x = x1;
  }
  flush(v);
  age = age + h;
  if (nonFinite(x, v)) {  // dies, with x = v = 0 (docs/model.md "Non-finite values")
    x = vec3(0.0);
    v = vec3(0.0);
    age = -1.0;
    return;
  }
  bool touched;
  if (contactFrom(x0, g.restitution, g.friction, -1.0, x, v, touched)) age = -1.0;
  if (kLifetimes != 0u && e.lifetime > 0.0 && age >= e.lifetime) age = -1.0;
}

// The state of one particle while an invocation advances it.
struct State {
  vec3 x;      // position (m)
  vec3 v;      // velocity (m/s)
  float age;   // s; < 0: not alive
  float m;     // kg
  uint k;      // its emitter
  uint first;  // first step of this dispatch to integrate (after its last birth)
};

// Loads particle `local` of the bound chunk and applies its last birth in this dispatch.
// Only the last birth matters: emission overwrites the whole particle. The dispatch's
// births of one emitter fill its ring contiguously from the first step's head, so the last
// one landing on this slot is found arithmetically and its step by a binary search over
// the running sums: the costly emission (hashes, rejection) runs once per dispatch, not
// masked in every step as SIMD drivers such as lavapipe would.
#ifdef LAVA_KERNEL_ONLY
// The compute ceiling of `lava bench`: the same steps with no emission and no schedule, the
// particles read once and written once for any number of steps (p.run.y).
State load(uint local) {
  Particle q = Particle(texelFetch(particleTexels, int(2u * local)),
                        texelFetch(particleTexels, int(2u * local + 1u)));
  State st = State(q.posAge.xyz, q.velMass.xyz, q.posAge.w, q.velMass.w, 0u, 0u);
  if (st.age < 0.0) st.first = p.run.y;
  return st;
}
#else
State load(uint local) {
  const uint slot = p.chunk.x + local;
  uint k = 0u;
  for (uint i = 1u; i < kEmitters; ++i)
    if (slot >= scene.emitters[i].ring.w) k = i;
  const uint steps = p.run.y;
  if (((kFlowEmitters >> k) & 1u) != 0u)  // flow.comp steps it: not stepped, not stored
    return State(vec3(0.0), vec3(0.0), -1.0, 0.0, k, steps);
  const uint capacity = scene.emitters[k].ring.z;
  const uint firstEntry = k * p.run.z + p.run.x;
  // Read through the texel view: each invocation reads its particles before it writes them,
  // and other invocations touch other particles.
  Particle q = Particle(texelFetch(particleTexels, int(2u * local)),
                        texelFetch(particleTexels, int(2u * local + 1u)));
  State st = State(q.posAge.xyz, q.velMass.xyz, q.posAge.w, q.velMass.w, k, 0u);
  if (kBirths == 0u) {  // none of this dispatch's births lands on this workgroup's particles
    if (st.age < 0.0) st.first = steps;
    return st;
  }
  const uint ringSlot = slot - scene.emitters[k].ring.w;
  uvec4 start = schedule[firstEntry].ring;
  uint base = schedule[firstEntry].sums.x;
  EmitEntry last = schedule[firstEntry + steps - 1u];
  uint total = last.sums.x + last.ring.y - base;  // births in this dispatch (host keeps < 2^31)
  uint rel = ringSlot >= start.x ? ringSlot - start.x : ringSlot + capacity - start.x;
  if (rel < total) {
    uint birth = rel + ((total - 1u - rel) / capacity) * capacity;  // index of the last birth
    uint lo = 0u;
    uint hi = steps - 1u;
    while (lo < hi) {  // the last step whose births start at or before `birth`
      uint mid = (lo + hi + 1u) >> 1u;
      if (schedule[firstEntry + mid].sums.x - base <= birth) {
        lo = mid;
      } else {
        hi = mid - 1u;
      }
    }
    uint serialLo = start.z + birth;
    uint serialHi = start.w + (serialLo < start.z ? 1u : 0u);
    precise vec3 x, v;
    emit(k, serialLo, serialHi, x, v);
    st.x = x;
    st.v = v;
    st.age = 0.0;
    st.m = scene.emitters[k].velocity.w;
    st.first = lo;
  }
  if (st.age < 0.0) st.first = steps;  // not alive and not born: not stepped, not stored
  return st;
}
#endif

// Four particles per invocation, a + k * stride: their step chains are independent, so
// interleaving them hides each one's latency (lavapipe runs one SIMD vector of invocations
// at a time).
void main() {
  const uint steps = p.run.y;
  const uint count = p.chunk.y;
  const uint stride = (count + kParticlesPerInvocation - 1u) / kParticlesPerInvocation;
  const uint a = p.chunk.z + gl_GlobalInvocationID.x;
  if (a >= stride) return;
  const State none = State(vec3(0.0), vec3(0.0), -1.0, 0.0, 0u, steps);
  State s0 = load(a);
  State s1 = a + stride < count ? load(a + stride) : none;
  State s2 = a + 2u * stride < count ? load(a + 2u * stride) : none;
  State s3 = a + 3u * stride < count ? load(a + 3u * stride) : none;
  precise vec3 x0 = s0.x, v0 = s0.v, x1 = s1.x, v1 = s1.v, x2 = s2.x, v2 = s2.v, x3 = s3.x, v3 = s3.v;
  precise float age0 = s0.age, age1 = s1.age, age2 = s2.age, age3 = s3.age;
  const World g = World(scene.world.x, scene.world.w, scene.world.y, scene.world.z, scene.wind.xyz);
  const Model m0 = model(s0.k), m1 = model(s1.k), m2 = model(s2.k), m3 = model(s3.k);
  // Without lifetimes an alive particle stays alive: only its first step needs checking.
  const bool deaths = kLifetimes != 0u;
  for (uint s = min(min(s0.first, s1.first), min(s2.first, s3.first)); s < steps; ++s) {
    if (s >= s0.first && (!deaths || age0 >= 0.0)) step(g, m0, x0, v0, age0);
    if (s >= s1.first && (!deaths || age1 >= 0.0)) step(g, m1, x1, v1, age1);
    if (s >= s2.first && (!deaths || age2 >= 0.0)) step(g, m2, x2, v2, age2);
    if (s >= s3.first && (!deaths || age3 >= 0.0)) step(g, m3, x3, v3, age3);
  }
  if (s0.first < steps) particles[a] = Particle(vec4(x0, age0), vec4(v0, s0.m));
  if (s1.first < steps) particles[a + stride] = Particle(vec4(x1, age1), vec4(v1, s1.m));
  if (s2.first < steps) particles[a + 2u * stride] = Particle(vec4(x2, age2), vec4(v2, s2.m));
  if (s3.first < steps) particles[a + 3u * stride] = Particle(vec4(x3, age3), vec4(v3, s3.m));
}
