#version 460
// One dispatch advances every particle of the bound range by run.w steps of SPEC §2:
// emit (from the host's ring schedule), explicit Euler, ground impulse. Particles are
// independent, so each invocation keeps its particle in registers across the steps.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(local_size_x_id = 0) in;

layout(std430, binding = kParticleBinding) restrict buffer Particles {
  Particle particles[];
};
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

void main() {
  uint local = gl_GlobalInvocationID.x;
  if (local >= p.chunk.y) {
    return;
  }
  uint slot = p.chunk.x + local;
  uint capacity = p.run.y;

  // Only the last birth of this slot within the dispatch matters: emission overwrites the
  // whole particle. The dispatch's births fill the ring contiguously from the first step's
  // head, so the last one landing on this slot is found arithmetically and its step by a
  // binary search over the running sums: the costly emission (hashes, disc rejection) runs
  // once per dispatch, not masked in every step as SIMD drivers such as lavapipe would.
  const uint firstEntry = p.run.z;
  const uint steps = p.run.w;
  uvec4 start = schedule[firstEntry].ring;
  uint base = schedule[firstEntry].sums.x;
  EmitEntry last = schedule[firstEntry + steps - 1u];
  uint total = last.sums.x + last.ring.y - base;  // births in this dispatch (host keeps < 2^31)
  uint rel = slot >= start.x ? slot - start.x : slot + capacity - start.x;
  uint born = steps;  // none
  uint serialLo = 0u;
  uint serialHi = 0u;
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
    born = lo;
    serialLo = start.z + birth;
    serialHi = start.w + (serialLo < start.z ? 1u : 0u);
  }

  Particle q = particles[local];
  precise vec3 x = q.posAge.xyz;
  precise vec3 v = q.velMass.xyz;
  precise float age = q.posAge.w;
  precise float m = q.velMass.w;
  uint first = 0u;
  if (born < steps) {
    emit(serialLo, serialHi, x, v);
    age = 0.0;
    m = p.material.z;
    first = born;
  }
  if (age < 0.0) {
    return;  // never emitted: the slot stays as it is
  }

  precise float h = p.velocity.w;
  precise float g = p.spread.w;
  precise float hm = h / m;                    // the same quotient and product the
  precise float weight = p.wind.y - m * g;     // reference computes every step
  for (uint s = first; s < steps; ++s) {
    // Explicit Euler: position with the start-of-step velocity, then velocity.
    precise vec3 v0 = v;
    x = x + h * v0;
    precise vec3 f = vec3(p.wind.x, weight, p.wind.z) - p.wind.w * v0;
    v = v0 + hm * f;
    age = age + h;
    // Ground impulse (seed eq. 7) with tangential damping and static friction.
    if (x.y < 0.0) {
      x.y = 0.0;
      if (v.y < 0.0) {
        v.x = p.material.y * v.x;
        v.z = p.material.y * v.z;
        v.y = -(p.material.x * v.y);
        if (abs(v.x) < kRestSpeed) v.x = 0.0;
        if (abs(v.z) < kRestSpeed) v.z = 0.0;
      }
    }
  }
  particles[local] = Particle(vec4(x, age), vec4(v, m));
}
