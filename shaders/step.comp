#version 460
// One dispatch advances every particle of the bound range by run.w steps of SPEC §2:
// emit (from the host's ring schedule), explicit Euler, ground impulse. Particles are
// independent, so each invocation keeps its particle in registers across the steps.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = kParticleBinding) writeonly buffer Particles {
  Particle particles[];
};
layout(binding = kParticleTexelBinding) uniform samplerBuffer particleTexels;  // same memory
layout(std430, binding = kScheduleBinding) restrict readonly buffer Schedule {
  EmitEntry schedule[];
};
layout(push_constant) uniform Push {
  StepParams p;
};

// Every float operation below is `precise`: no contraction into FMA, no reassociation,
// so the result is the IEEE float32 sequence the CPU reference computes.
void emit(uint serialLo, uint serialHi, inout vec3 x, inout vec3 v) {
  precise vec3 u;
  u.x = signedUnit(randomBits(p.run.x, serialLo, serialHi, 0u));
  u.y = signedUnit(randomBits(p.run.x, serialLo, serialHi, 1u));
  u.z = signedUnit(randomBits(p.run.x, serialLo, serialHi, 2u));
  precise float dx = 0.0;
  precise float dz = 0.0;
  for (uint t = 0u; t < kDiscTries; ++t) {
    precise float a = signedUnit(randomBits(p.run.x, serialLo, serialHi, kVelocityComponents + 2u * t));
    precise float b = signedUnit(randomBits(p.run.x, serialLo, serialHi, kVelocityComponents + 2u * t + 1u));
    precise float r2 = a * a + b * b;
    if (r2 <= 1.0) {
      dx = a;
      dz = b;
      break;
    }
  }
  precise float radius = p.emitter.w;
  x.x = p.emitter.x + radius * dx;
  x.y = p.emitter.y;
  x.z = p.emitter.z + radius * dz;
  v.x = p.velocity.x + p.spread.x * u.x;
  v.y = p.velocity.y + p.spread.y * u.y;
  v.z = p.velocity.z + p.spread.z * u.z;
}

// The state of one particle while an invocation advances it.
struct State {
  vec3 x;      // position (m)
  vec3 v;      // velocity (m/s)
  float age;   // s; < 0: never emitted
  float m;     // kg
  uint first;  // first step of this dispatch to integrate (after its last birth)
};

// Loads particle `local` of the bound range and applies its last birth in this dispatch.
// Only the last birth matters: emission overwrites the whole particle. The dispatch's
// births fill the ring contiguously from the first step's head, so the last one landing on
// this slot is found arithmetically and its step by a binary search over the running sums:
// the costly emission (hashes, disc rejection) runs once per dispatch, not masked in every
// step as SIMD drivers such as lavapipe would.
State load(uint local) {
  const uint capacity = p.run.y;
  const uint firstEntry = p.run.z;
  const uint steps = p.run.w;
  // Read through the texel view: each invocation reads its particles before it writes them,
  // and other invocations touch other particles.
  Particle q = Particle(texelFetch(particleTexels, int(2u * local)),
                        texelFetch(particleTexels, int(2u * local + 1u)));
  State st = State(q.posAge.xyz, q.velMass.xyz, q.posAge.w, q.velMass.w, 0u);
  uint slot = p.chunk.x + local;
  uvec4 start = schedule[firstEntry].ring;
  uint base = schedule[firstEntry].sums.x;
  EmitEntry last = schedule[firstEntry + steps - 1u];
  uint total = last.sums.x + last.ring.y - base;  // births in this dispatch (host keeps < 2^31)
  uint rel = slot >= start.x ? slot - start.x : slot + capacity - start.x;
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
    emit(serialLo, serialHi, st.x, st.v);
    st.age = 0.0;
    st.m = p.material.z;
    st.first = lo;
  }
  if (st.age < 0.0) st.first = steps;  // never emitted: not stepped, not stored
  return st;
}

// One step of SPEC §2 (after emission). `hm` = h/m and `weight` = wind.y - m g are the
// same quotient and product the reference computes every step.
void integrate(inout vec3 x, inout vec3 v, inout float age, float hm, float weight) {
  precise float h = p.velocity.w;
  // Explicit Euler: position with the start-of-step velocity, then velocity.
  precise vec3 v0 = v;
  precise vec3 x1 = x + h * v0;
  precise vec3 f = vec3(p.wind.x, weight, p.wind.z) - p.wind.w * v0;
  precise vec3 v1 = v0 + hm * f;
  age = age + h;
  // Ground impulse (seed eq. 7) with tangential damping and static friction.
  if (x1.y < 0.0) {
    x1.y = 0.0;
    if (v1.y < 0.0) {
      v1.x = p.material.y * v1.x;
      v1.z = p.material.y * v1.z;
      v1.y = -(p.material.x * v1.y);
      if (abs(v1.x) < kRestSpeed) v1.x = 0.0;
      if (abs(v1.z) < kRestSpeed) v1.z = 0.0;
    }
  }
  x = x1;
  v = v1;
}

// Four particles per invocation, a + k * stride: their step chains are independent, so
// interleaving them hides each one's latency (lavapipe runs one SIMD vector of invocations
// at a time: 2x faster with two particles, 2.5x with four, at 262,144 particles).
void main() {
  const uint steps = p.run.w;
  const uint stride = (p.chunk.y + kParticlesPerInvocation - 1u) / kParticlesPerInvocation;
  uint a = gl_GlobalInvocationID.x;
  if (a >= stride) return;
  State s0 = load(a);
  State s1 = a + stride < p.chunk.y ? load(a + stride) : State(vec3(0.0), vec3(0.0), -1.0, 1.0, steps);
  State s2 = a + 2u * stride < p.chunk.y ? load(a + 2u * stride) : State(vec3(0.0), vec3(0.0), -1.0, 1.0, steps);
  State s3 = a + 3u * stride < p.chunk.y ? load(a + 3u * stride) : State(vec3(0.0), vec3(0.0), -1.0, 1.0, steps);
  precise vec3 x0 = s0.x, v0 = s0.v, x1 = s1.x, v1 = s1.v, x2 = s2.x, v2 = s2.v, x3 = s3.x, v3 = s3.v;
  precise float age0 = s0.age, age1 = s1.age, age2 = s2.age, age3 = s3.age;
  precise float g = p.spread.w;
  precise float h = p.velocity.w;
  precise float hm0 = h / s0.m, hm1 = h / s1.m, hm2 = h / s2.m, hm3 = h / s3.m;
  precise float w0 = p.wind.y - s0.m * g, w1 = p.wind.y - s1.m * g, w2 = p.wind.y - s2.m * g, w3 = p.wind.y - s3.m * g;
  for (uint s = min(min(s0.first, s1.first), min(s2.first, s3.first)); s < steps; ++s) {
    if (s >= s0.first) integrate(x0, v0, age0, hm0, w0);
    if (s >= s1.first) integrate(x1, v1, age1, hm1, w1);
    if (s >= s2.first) integrate(x2, v2, age2, hm2, w2);
    if (s >= s3.first) integrate(x3, v3, age3, hm3, w3);
  }
  if (s0.first < steps) particles[a] = Particle(vec4(x0, age0), vec4(v0, s0.m));
  if (s1.first < steps) particles[a + stride] = Particle(vec4(x1, age1), vec4(v1, s1.m));
  if (s2.first < steps) particles[a + 2u * stride] = Particle(vec4(x2, age2), vec4(v2, s2.m));
  if (s3.first < steps) particles[a + 3u * stride] = Particle(vec4(x3, age3), vec4(v3, s3.m));
}
