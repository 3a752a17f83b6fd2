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
  Particle q = particles[local];
  precise vec3 x = q.posAge.xyz;
  precise vec3 v = q.velMass.xyz;
  precise float age = q.posAge.w;
  precise float m = q.velMass.w;
  precise float h = p.velocity.w;
  precise float g = p.spread.w;
  uint capacity = p.run.y;

  for (uint s = 0u; s < p.run.w; ++s) {
    uvec4 ring = schedule[p.run.z + s].ring;
    uint rel = slot >= ring.x ? slot - ring.x : slot + capacity - ring.x;
    if (rel < ring.y) {
      uint serialLo = ring.z + rel;
      uint serialHi = ring.w + (serialLo < ring.z ? 1u : 0u);
      emit(serialLo, serialHi, x, v);
      age = 0.0;
      m = p.material.z;
    }
    if (age < 0.0) {
      continue;
    }
    // Explicit Euler: position with the start-of-step velocity, then velocity.
    precise vec3 v0 = v;
    x = x + h * v0;
    precise vec3 f = vec3(p.wind.x, p.wind.y - m * g, p.wind.z) - p.wind.w * v0;
    v = v0 + (h / m) * f;
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
