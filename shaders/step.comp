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

// What every particle's steps need of the scene, read once per dispatch.
struct World {
  float h;            // step (s)
  float drag;         // N s/m
  float restitution;  // the ground's
  float friction;
  vec3 wind;          // N
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

// |v_i| < 2^-24 becomes +0: denormals never enter the state.
void flush(inout precise vec3 v) {
  v.x = abs(v.x) < kTinySpeed ? 0.0 : v.x;
  v.y = abs(v.y) < kTinySpeed ? 0.0 : v.y;
  v.z = abs(v.z) < kTinySpeed ? 0.0 : v.z;
}

// Emission: the particle of emitter k with this serial.
void emit(uint k, uint lo, uint hi, out precise vec3 x, out precise vec3 v) {
  const EmitterParams e = scene.emitters[k];
  const uint seed = e.ring.y;
  precise vec3 u = vec3(signedUnit(randomBits(seed, lo, hi, 0u)),
                        signedUnit(randomBits(seed, lo, hi, 1u)),
                        signedUnit(randomBits(seed, lo, hi, 2u)));
  precise vec3 o = vec3(0.0);
  const uint shape = e.ring.x;
  precise float r = e.position.w;
  if (shape == kShapeDisc) {
    precise float a = 0.0, b = 0.0;
    for (uint t = 0u; t < kDiscTries; ++t) {
      precise float ta = signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 2u * t));
      precise float tb = signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 1u + 2u * t));
      precise float r2 = ta * ta + tb * tb;
      if (r2 <= 1.0) {
        a = ta;
        b = tb;
        break;
      }
    }
    o = vec3(r * a, 0.0, r * b);
  } else if (shape == kShapeSphere) {
    precise vec3 c = vec3(0.0);
    for (uint t = 0u; t < kSphereTries; ++t) {
      precise vec3 tc = vec3(signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 3u * t)),
                             signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 1u + 3u * t)),
                             signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 2u + 3u * t)));
      precise float r2 = (tc.x * tc.x + tc.y * tc.y) + tc.z * tc.z;
      if (r2 <= 1.0) {
        c = tc;
        break;
      }
    }
    o = r * c;
  } else if (shape == kShapeBox) {
    precise vec3 c = vec3(signedUnit(randomBits(seed, lo, hi, kVelocityComponents)),
                          signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 1u)),
                          signedUnit(randomBits(seed, lo, hi, kVelocityComponents + 2u)));
    o = e.size.xyz * c;
  }
  x = e.position.xyz + o;
  v = e.velocity.xyz + e.spread.xyz * u;
  flush(v);
}

// F(x, v): wind and gravity (w = wind.y - m g, from the host), drag, then the forces.
void force(const World g, precise vec3 x, precise vec3 v, float w, out precise vec3 f) {
  f = vec3(g.wind.x, w, g.wind.z) - g.drag * v;
  [[unroll]] for (uint i = 0u; i < kForces; ++i) {
    const ForceParams F = scene.forces[i];
    precise float k = F.position.w;
    if (((kForceKinds >> i) & 1u) == kAttractor) {
      precise vec3 d = F.position.xyz - x;
      precise float dd = (d.x * d.x + d.y * d.y) + d.z * d.z;
      if (F.kind.y != 0u || dd <= F.axis.w) f = f + k * d;
    } else {
      precise vec3 d = x - F.position.xyz;
      const vec3 a = F.axis.xyz;
      precise vec3 c = vec3(a.y * d.z - a.z * d.y, a.z * d.x - a.x * d.z, a.x * d.y - a.y * d.x);
      f = f + k * c;
    }
  }
}

// R(n, ε, α) for a projected particle: restitution on the normal speed, retention (and
// static friction) on the tangential velocity.
void respond(inout precise vec3 v, precise vec3 n, float restitution, float friction) {
  precise float vn = (v.x * n.x + v.y * n.y) + v.z * n.z;
  if (vn < 0.0) {
    precise vec3 t = v - vn * n;
    precise vec3 kept = friction * t;
    if (abs(kept.x) < kRestSpeed) kept.x = 0.0;
    if (abs(kept.y) < kRestSpeed) kept.y = 0.0;
    if (abs(kept.z) < kRestSpeed) kept.z = 0.0;
    precise float e = -(restitution * vn);
    v = kept + e * n;
  }
}

// 1/sqrt(q) for q > 0 from the bit pattern and three Newton steps: only adds and
// multiplies, so every conforming driver computes the same bits.
float inverseRoot(precise float q) {
  precise float y = uintBitsToFloat(kRsqrtMagic - (floatBitsToUint(q) >> 1u));
  precise float halfQ = 0.5 * q;
  y = y * (1.5 - (halfQ * y) * y);
  y = y * (1.5 - (halfQ * y) * y);
  y = y * (1.5 - (halfQ * y) * y);
  return y;
}

// The solid truncated cone (README "The crater"): pushed out through its top or its side,
// whichever is nearer, a margin beyond the surface.
void cone(const ColliderParams c, inout precise vec3 x, inout precise vec3 v) {
  precise vec3 d = x - c.position.xyz;
  const float height = c.shape.z;
  if (d.y >= 0.0 && d.y < height) {
    precise float ry = c.shape.x + c.shape.y * d.y;
    precise float q = d.x * d.x + d.z * d.z;
    precise float rr = ry * ry;
    if (q < rr) {
      precise float rx = 1.0, rz = 0.0, rho = 0.0;
      if (q >= kAxisSquared) {
        precise float inv = inverseRoot(q);
        rx = d.x * inv;
        rz = d.z * inv;
        rho = q * inv;
      }
      precise float side = (ry - rho) * c.cone.x;
      precise float up = height - d.y;
      precise vec3 n;
      if (up <= side) {
        x.y = c.cone.z;
        n = vec3(0.0, 1.0, 0.0);
      } else {
        n = vec3(c.cone.x * rx, c.cone.y, c.cone.x * rz);
        precise float move = side + c.cone.w;
        x = x + move * n;
      }
      respond(v, n, c.material.x, c.material.y);
      flush(v);
    }
  }
}

void collide(const ColliderParams c, uint type, inout precise vec3 x, inout precise vec3 v) {
  if (type == kPlane) {
    precise vec3 n = c.shape.xyz;
    precise vec3 r = x - c.position.xyz;
    precise float dist = (r.x * n.x + r.y * n.y) + r.z * n.z;
    if (dist < 0.0) {
      x = x - dist * n;
      respond(v, n, c.material.x, c.material.y);
      flush(v);
    }
  } else if (type == kSphere) {
    precise vec3 d = x - c.position.xyz;
    precise float q = (d.x * d.x + d.y * d.y) + d.z * d.z;
    if (q < c.shape.y) {
      precise vec3 n = vec3(0.0, 1.0, 0.0);
      if (q != 0.0) {
        precise float s = sqrt(q);  // the model's one square root and division
        n = vec3(d.x / s, d.y / s, d.z / s);
      }
      x = c.position.xyz + c.shape.x * n;
      respond(v, n, c.material.x, c.material.y);
      flush(v);
    }
  } else if (type == kBox) {
    precise vec3 d = x - c.position.xyz;
    const vec3 e = c.shape.xyz;
    if (abs(d.x) < e.x && abs(d.y) < e.y && abs(d.z) < e.z) {
      precise vec3 gap = e - abs(d);
      uint j = 0u;
      if (gap.y < gap.x) j = 1u;
      if (gap.z < (j == 0u ? gap.x : gap.y)) j = 2u;
      precise float sigma = d[j] >= 0.0 ? 1.0 : -1.0;
      x[j] = c.position[j] + sigma * e[j];
      precise vec3 n = vec3(0.0);
      n[j] = sigma;
      respond(v, n, c.material.x, c.material.y);
      flush(v);
    }
  } else {
    cone(c, x, v);
  }
}

// One step of an alive particle (after any birth).
void step(const World g, const Model e, inout precise vec3 x, inout precise vec3 v,
          inout precise float age) {
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
  } else {  // explicit Euler (the seed): position with the start-of-step velocity
    precise vec3 x1 = x + h * v;
    v = v + hm * f;
    x = x1;
  }
  flush(v);
  age = age + h;
  // The ground: restitution on y, retention and static friction on x and z.
  if (x.y < 0.0) {
    x.y = 0.0;
    if (v.y < 0.0) {
      v.x = g.friction * v.x;
      v.z = g.friction * v.z;
      v.y = -(g.restitution * v.y);
      if (abs(v.x) < kRestSpeed) v.x = 0.0;
      if (abs(v.z) < kRestSpeed) v.z = 0.0;
      flush(v);
    }
  }
  [[unroll]] for (uint i = 0u; i < kColliders; ++i)  // each slot's kind then a constant
    collide(scene.colliders[i], (kColliderKinds >> (2u * i)) & 3u, x, v);
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
  const uint capacity = scene.emitters[k].ring.z;
  const uint steps = p.run.y;
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
// at a time; docs/benchmarks-history.md).
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
