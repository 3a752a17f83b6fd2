#version 460
// One pass of one step of the flow (docs/model.md, "The flow"), on the flow's own copy of its
// particles, their temperatures and crust flags: the step's births and the grid (births,
// scan, starts, scatter, order), then the two neighbour passes (density, forces and the
// step), then the results over the state (store). The host records the eight passes per step,
// with a barrier between each, and copies the flow's particles into the state's chunks after
// the last step it records.
//
// Exactness: as step.comp (every float `precise`, the operations in flow/cpu_flow.cpp's order, no
// square root or division), and every neighbour sum in an order fixed by the state: the
// buckets' slots are put in flow index order (kFlowOrder) whatever order the scatter's atomics
// gave them, and the 27 cells are visited z, y, x from -1 to +1.
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
layout(constant_id = kForcesConstant) const uint kForces = 0u;
layout(constant_id = kCollidersConstant) const uint kColliders = 0u;
layout(constant_id = kForceKindsConstant) const uint kForceKinds = 0u;
layout(constant_id = kColliderKindsConstant) const uint kColliderKinds = 0u;

layout(std430, binding = kFlowParticleBinding) restrict buffer Particles {
  Particle particles[];
};
layout(std430, binding = kScheduleBinding) restrict readonly buffer Schedule {
  EmitEntry schedule[];
};
layout(std430, binding = kFlowHeatBinding) restrict buffer Heat {
  FlowHeat heat[];
};
layout(std140, binding = kSceneBinding) uniform Scene {
  SceneParams scene;
};
layout(std140, binding = kFlowParamsBinding) uniform Flow {
  FlowParams flow;
};
layout(std430, binding = kFlowNextBinding) restrict buffer Next {
  FlowNext next[];
};
layout(std430, binding = kFlowScratchBinding) restrict buffer Scratch {
  FlowScratch scratch[];
};
layout(std430, binding = kFlowGridBinding) restrict buffer Grid {
  uint grid[];  // counts[buckets], start[buckets + 1], sorted[flow slots]
};
layout(push_constant) uniform Push {
  FlowStepParams p;
};

#include "model.glsl"

shared uint partial[kWorkgroupSize];

uint buckets() {
  return flow.sizes.x;
}
uint startAt(uint b) {
  return buckets() + b;
}
uint sortedAt(uint e) {
  return 2u * buckets() + 1u + e;
}
uint runs() {
  return buckets() / kFlowRun;
}
uint runCountAt(uint r) {
  return 2u * buckets() + 1u + flow.sizes.y + r;
}
uint runStartAt(uint r) {
  return runCountAt(runs() + r);
}
uint blocks() {
  return runs() / kFlowBlock;
}
uint blockCountAt(uint k) {
  return runStartAt(runs() + k);
}
uint blockStartAt(uint k) {
  return blockCountAt(blocks() + k);
}

// The flow emitter (an index into flow.emitters) of flow index f.
uint flowEmitter(uint f) {
  uint e = 0u;
  for (uint i = 1u; i < flow.sizes.z; ++i)
    if (f >= flow.emitters[i].slots.y) e = i;
  return e;
}

// Pair terms below the tiny term become +0: no denormal enters a sum.
float tiny(precise float term) {
  return abs(term) < flow.limits.y ? 0.0 : term;
}

// 1/q from 1/sqrt(q) squared.
float reciprocal(precise float q) {
  precise float y = inverseRoot(q);
  precise float r = y * y;
  return r;
}

// At most 1: the factor that keeps a particle's exchange rates summing to at most 1/2.
float stable(precise float rate) {
  precise float r = 1.0;
  if (rate > 0.5) r = 0.5 * reciprocal(rate);
  return r;
}

ivec3 cellOf(precise vec3 x) {
  precise vec3 u = x * flow.kernel.x;
  const float limit = flow.limits.w;
  u = min(max(u, vec3(-limit)), vec3(limit - 1.0));
  return ivec3(floor(u));
}

uint bucketOf(ivec3 c) {
  return ((uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u)) &
         (buckets() - 1u);
}

float tableAt(uint i) {
  return flow.table[i >> 2u][i & 3u];
}

// The viscosity at temperature t: the table, interpolated; exact at both ends.
float viscosityAt(precise float t) {
  if (t >= flow.heat.y) return flow.rates.x;
  if (t <= flow.heat.x) return flow.rates.y;
  precise float x = (t - flow.heat.x) * flow.heat.w;
  const uint i = min(uint(x), kViscosityEntries - 2u);
  precise float f = x - float(i);
  precise float a = tableAt(i);
  precise float b = tableAt(i + 1u);
  precise float r = a + f * (b - a);
  return r;
}

// The distance of a pair and its unit direction n from j to i: coincident pairs are pushed
// apart along x, the lower flow index (and slot) towards -x.
float pairDistance(precise float q, precise vec3 d, uint i, uint j, out precise vec3 n) {
  if (!(q >= flow.limits.z)) {
    n = vec3(i < j ? -1.0 : 1.0, 0.0, 0.0);
    return 0.0;
  }
  precise float inv = inverseRoot(q);
  n = inv * d;
  precise float r = q * inv;
  return r;
}

// floor(sqrt(m)) digit by digit in integers (flow/lattice.cpp): no float operation.
uint integerRoot(uint m) {
  uint root = 0u, bit = 1u << 30;
  while (bit > m) bit >>= 2;
  for (; bit != 0u; bit >>= 2) {
    if (m >= root + bit) {
      m -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
  }
  return root;
}

// A ball's row (j, k): 2 w + 1 sites, w its half-width; 0 outside.
uint rowSites(const uvec4 s, int j, int k) {
  const int rest = int(s.y) - j * j - k * k;
  return rest < 0 ? 0u : 2u * integerRoot(uint(rest)) + 1u;
}

// Lattice site `index` of a flow emitter, as integer offsets (flow/lattice.cpp's latticeSite):
// a box's along x, then z, then y; a ball's by layer from the bottom, row along z, then x.
ivec3 latticeSite(const uvec4 s, uint index) {
  if (s.x == kFillBox)
    return ivec3(int(index % s.y), int(index / (s.y * s.w)), int((index / s.y) % s.w));
  const int k = int(s.z), layers = int(s.w);
  uint rest = index;
  for (int y = -layers; y <= layers; ++y)
    for (int z = -k; z <= k; ++z) {
      const uint row = rowSites(s, y, z);
      if (rest < row) return ivec3(int(rest) - int(row / 2u), y, z);
      rest -= row;
    }
  return ivec3(0);
}

// The step's births (the last one landing on each slot wins, as on the host), then the
// slot's cell and bucket, counted, and what its neighbours will read of it.
void births(uint f) {
  const FlowEmitterParams fe = flow.emitters[flowEmitter(f)];
  const uint k = fe.slots.x;
  const uint capacity = fe.slots.w;
  const EmitEntry entry = schedule[k * p.run.z + p.run.x];
  const uint count = entry.ring.y;
  Particle q = particles[f];
  if (count > 0u) {
    const uint ringSlot = f - fe.slots.y;
    const uint head = entry.ring.x;
    const uint rel = ringSlot >= head ? ringSlot - head : ringSlot + capacity - head;
    if (rel < count) {
      const uint birth = rel + ((count - 1u - rel) / capacity) * capacity;
      const uint serialLo = entry.ring.z + birth;
      const uint serialHi = entry.ring.w + (serialLo < entry.ring.z ? 1u : 0u);
      precise vec3 x, v;
      if (fe.lattice.x == kFillRandom) {
        emit(k, serialLo, serialHi, x, v);
      } else {  // at rest on its lattice site (a lattice's serials are below its burst)
        const vec3 centre = fe.lattice.x == kFillBox ? fe.spacing.yzw : vec3(0.0);
        precise vec3 o = fe.spacing.x * (vec3(latticeSite(fe.lattice, serialLo)) - centre);
        x = scene.emitters[k].position.xyz + o;
        v = vec3(0.0);
      }
      q = Particle(vec4(x, 0.0), vec4(v, scene.emitters[k].velocity.w));
      particles[f] = q;
      heat[f] = FlowHeat(fe.weights.w, 0u);
    }
  }
  if (!(q.posAge.w < 0.0) && nonFinite(q.posAge.xyz, q.velMass.xyz)) {
    // Dies before any neighbour reads it (docs/model.md "Non-finite values").
    q = Particle(vec4(0.0, 0.0, 0.0, -1.0), vec4(0.0, 0.0, 0.0, q.velMass.w));
    particles[f] = q;
    heat[f] = FlowHeat(0.0, 0u);
  }
  if (q.posAge.w < 0.0) {
    scratch[f].cell = ivec4(0, 0, 0, int(kFlowUnsorted));
    return;
  }
  const ivec3 c = cellOf(q.posAge.xyz);
  const uint b = bucketOf(c);
  scratch[f].cell = ivec4(c, int(b));
  scratch[f].own = vec4(viscosityAt(heat[f].temperature), fe.weights.xyz);
  atomicAdd(grid[b], 1u);
  atomicAdd(grid[runCountAt(b / kFlowRun)], 1u);
  atomicAdd(grid[blockCountAt(b / (kFlowRun * kFlowBlock))], 1u);
}

// One workgroup: each block's start from the blocks' counts (the blocks in turns of
// consecutive blocks per invocation, then the turns' sums in order), each block's count back
// to 0; the total after the last bucket's start.
void scan(uint t) {
  const uint per = max(blocks() / kWorkgroupSize, 1u);
  const uint begin = min(t * per, blocks()), end = min(begin + per, blocks());
  uint sum = 0u;
  for (uint k = begin; k < end; ++k) sum += grid[blockCountAt(k)];
  partial[t] = sum;
  barrier();
  if (t == 0u) {
    uint running = 0u;
    for (uint i = 0u; i < kWorkgroupSize; ++i) {
      const uint s = partial[i];
      partial[i] = running;
      running += s;
    }
    grid[startAt(buckets())] = running;
  }
  barrier();
  uint running = partial[t];
  for (uint k = begin; k < end; ++k) {
    const uint count = grid[blockCountAt(k)];
    grid[blockStartAt(k)] = running;
    grid[blockCountAt(k)] = 0u;
    running += count;
  }
}

// Per block of kFlowBlock runs: their starts from the block's, and their counts back to 0
// (no barrier: every block at once).
void blockStarts(uint k) {
  const uint first = k * kFlowBlock;
  uint running = grid[blockStartAt(k)];
  for (uint r = first; r < first + kFlowBlock; ++r) {
    const uint count = grid[runCountAt(r)];
    grid[runStartAt(r)] = running;
    grid[runCountAt(r)] = 0u;
    running += count;
  }
}

// Per run of kFlowRun buckets: their starts from the run's, and their counts back to 0 for
// the scatter's cursors (no barrier: every run at once).
void starts(uint r) {
  const uint first = r * kFlowRun;
  uint running = grid[runStartAt(r)];
  for (uint b = first; b < first + kFlowRun; ++b) {
    const uint count = grid[b];
    grid[startAt(b)] = running;
    grid[b] = 0u;
    running += count;
  }
}

void scatter(uint f) {
  const uint b = uint(scratch[f].cell.w);
  if (b == kFlowUnsorted) return;
  grid[sortedAt(grid[startAt(b)] + atomicAdd(grid[b], 1u))] = f;
}

// A bucket's kFlowBucketCap lowest flow indices first, in order: all that the neighbour
// loops read of it (the rest keep the scatter's order, which nothing reads). Linear in the
// bucket: an insertion sort of its first slots, then each later slot compared with the
// largest kept and inserted only when smaller. Its count back to 0 for the next step.
void order(uint b) {
  const uint begin = grid[startAt(b)], end = grid[startAt(b + 1u)];
  const uint kept = begin + min(end - begin, kFlowBucketCap);
  for (uint e = begin + 1u; e < end; ++e) {
    const uint f = grid[sortedAt(e)];
    uint at = e;
    if (e >= kept) {  // a later slot: in only when below the largest kept, which goes to e
      at = kept - 1u;
      const uint largest = grid[sortedAt(at)];
      if (f >= largest) continue;
      grid[sortedAt(e)] = largest;
    }
    while (at > begin && grid[sortedAt(at - 1u)] > f) {
      grid[sortedAt(at)] = grid[sortedAt(at - 1u)];
      --at;
    }
    grid[sortedAt(at)] = f;
  }
  grid[b] = 0u;
}

// The number of a bucket's slots the neighbour loops read (at most kFlowBucketCap), one more
// for i's own home bucket when i lies beyond them: i is then read after them.
uint bucketReads(uint i, uint begin, uint end, bool home) {
  if (end - begin <= kFlowBucketCap) return end - begin;
  return kFlowBucketCap + (home && i > grid[sortedAt(begin + kFlowBucketCap - 1u)] ? 1u : 0u);
}

// The neighbour loops of both passes: every flow slot j within the radius of slot i (i
// included), the cells z, then y, then x, each bucket's first kFlowBucketCap slots in order
// (and i, if beyond them). BODY sees j, d, q, t.
#define LAVA_FOR_NEIGHBOURS(i, xi, BODY)                                              \
  {                                                                                 \
    const ivec3 home = scratch[i].cell.xyz;                                         \
    for (int dz = -1; dz <= 1; ++dz)                                                \
      for (int dy = -1; dy <= 1; ++dy)                                              \
        for (int dx = -1; dx <= 1; ++dx) {                                          \
          const ivec3 cell = home + ivec3(dx, dy, dz);                              \
          const uint b = bucketOf(cell);                                            \
          const uint begin = grid[startAt(b)];                                      \
          const uint reads = bucketReads(i, begin, grid[startAt(b + 1u)],           \
                                         dx == 0 && dy == 0 && dz == 0);            \
          for (uint nr = 0u; nr < reads; ++nr) {                                    \
            const uint j = nr < kFlowBucketCap ? grid[sortedAt(begin + nr)] : i;    \
            if (scratch[j].cell.xyz != cell) continue;                              \
            precise vec3 d = xi - particles[j].posAge.xyz;                          \
            precise float q = (d.x * d.x + d.y * d.y) + d.z * d.z;                  \
            precise float t = 1.0 - q * flow.kernel.y;                              \
            if (!(t > flow.limits.x)) continue;                                     \
            BODY                                                                    \
          }                                                                         \
        }                                                                           \
  }

// Pass 1: the density ratio theta, the exchange rates' stability factors, and whether a
// solid particle touches crust.
void density(uint i) {
  if (uint(scratch[i].cell.w) == kFlowUnsorted) return;
  const vec3 xi = particles[i].posAge.xyz;
  precise float theta = 0.0, viscous = 0.0, conductive = 0.0;
  bool touches = false;
  precise float nu = scratch[i].own.x;
  LAVA_FOR_NEIGHBOURS(i, xi, {
    const vec4 oj = scratch[j].own;  // nu and the density, pressure and Laplacian weights
    precise vec3 n;
    precise float r = pairDistance(q, d, i, j, n);
    precise float tr = max(1.0 - r * flow.kernel.x, 0.0);
    theta = theta + oj.y * ((tr * tr) * tr);
    if (j != i) {
      precise float t2 = t * t;
      viscous = viscous + tiny((oj.w * (nu + oj.x)) * t2);
      conductive = conductive + tiny(oj.w * t2);
      touches = touches || (heat[j].crust != 0u && q < flow.kernel.z);
    }
  })
  precise float inverse = reciprocal(theta);
  precise float pi = ((flow.kernel.w * max(theta - 1.0, 0.0)) * inverse) * inverse;
  precise float conduction = flow.contact.x * conductive;
  scratch[i].rates = vec4(pi, stable(viscous), stable(conduction), touches ? 1.0 : 0.0);
}

// The step of a slot that is not crust, from its pass-2 sums a and dv: a liquid moves under
// viscosity, pressure and the forces, a solid touching crust becomes crust where it is, a
// cinder falls; then the contact with the ground and the solids.
void move(World g, uint k, Particle pi, bool liquid, bool touchesCrust, vec3 a, vec3 dv,
          inout vec3 position, inout vec3 velocity, inout bool touched, inout bool becomesCrust,
          inout bool dies) {
  precise float h = g.h;
  precise vec3 x = position, v = velocity;
  const EmitterParams ep = scene.emitters[k];
  precise float hm = ep.size.w;
  precise vec3 f;
  if (liquid) {  // viscosity, then a semi-implicit Euler step with pressure and the forces
    v = v + dv;
    flush(v);
    force(g, x, v, ep.constants.z, f);
    v = (v + hm * f) + h * a;
    flush(v);
    x = x + h * v;
  } else if (touchesCrust) {  // a solid touching crust: crust where it is
    becomesCrust = true;
  } else {  // a cinder: falls as any particle
    force(g, x, v, ep.constants.z, f);
    v = v + hm * f;
    flush(v);
    x = x + h * v;
  }
  if (!becomesCrust && nonFinite(x, v)) {  // docs/model.md "Non-finite values"
    x = vec3(0.0);
    v = vec3(0.0);
    dies = true;
  } else if (!becomesCrust) {
    dies = contactFrom(pi.posAge.xyz, flow.contact.y, g.friction, flow.contact.y, x, v,
                       touched);
    becomesCrust = !liquid && touched;
  }
  if (becomesCrust) v = vec3(0.0);
  position = x;
  velocity = v;
}

// Pass 2 and the step: every slot reads the start-of-step state of the others and writes
// its results to next[].
void forces(uint i) {
  if (uint(scratch[i].cell.w) == kFlowUnsorted) return;
  const uint k = flow.emitters[flowEmitter(i)].slots.x;
  const Particle pi = particles[i];
  const FlowHeat hi = heat[i];
  const vec4 ri = scratch[i].rates;
  const bool isCrust = hi.crust != 0u;
  const bool liquid = !isCrust && hi.temperature > flow.heat.x;
  precise float nu = scratch[i].own.x;
  precise vec3 a = vec3(0.0), dv = vec3(0.0);
  precise float dT = 0.0;
  const vec3 xi = pi.posAge.xyz;
  LAVA_FOR_NEIGHBOURS(i, xi, {
    if (j != i) {
      const vec4 oj = scratch[j].own;  // nu and the density, pressure and Laplacian weights
      const FlowHeat hj = heat[j];
      const vec4 rj = scratch[j].rates;
      precise float t2 = t * t;
      precise float heatTerm = (((oj.w * flow.contact.x) * t2) * min(ri.z, rj.z)) *
                               (hj.temperature - hi.temperature);
      dT = dT + tiny(heatTerm);
      if (liquid) {
        const vec3 vj = particles[j].velMass.xyz;
        precise vec3 n;
        precise float r = pairDistance(q, d, i, j, n);
        precise float tr = max(1.0 - r * flow.kernel.x, 0.0);
        precise float push = (oj.z * (ri.x + rj.x)) * (tr * tr);
        a = a + vec3(tiny(push * n.x), tiny(push * n.y), tiny(push * n.z));
        precise float rate = ((oj.w * (nu + oj.x)) * t2) * min(ri.y, rj.y);
        precise vec3 dvj = vj - pi.velMass.xyz;
        dv = dv + vec3(tiny(rate * dvj.x), tiny(rate * dvj.y), tiny(rate * dvj.z));
      }
    }
  })

  const World g =
      World(scene.world.x, scene.world.w, scene.world.y, scene.world.z, scene.wind.xyz);
  precise float h = g.h;
  precise vec3 x = pi.posAge.xyz, v = pi.velMass.xyz;
  bool touched = false, becomesCrust = isCrust, dies = false;
  if (!isCrust) move(g, k, pi, liquid, ri.w != 0.0, a, dv, x, v, touched, becomesCrust, dies);
  precise float cool = touched ? flow.rates.w : flow.rates.z;
  precise float t1 = (hi.temperature + dT) - cool * (hi.temperature - flow.heat.z);
  precise float age = pi.posAge.w + h;
  const float lifetime = scene.emitters[k].spread.w;
  if (dies || (lifetime > 0.0 && age >= lifetime)) {  // an unborn slot's temperature and flag
    age = -1.0;
    t1 = 0.0;
    becomesCrust = false;
  }
  next[i] = FlowNext(vec4(x, age), vec4(v, pi.velMass.w),
                     vec4(t1, becomesCrust ? 1.0 : 0.0, 0.0, 0.0));
}

void store(uint f) {
  if (uint(scratch[f].cell.w) == kFlowUnsorted) return;
  const FlowNext r = next[f];
  particles[f] = Particle(r.posAge, r.velMass);
  heat[f] = FlowHeat(r.heat.x, r.heat.y != 0.0 ? 1u : 0u);
}

void main() {
  const uint pass = p.run.y;
  if (pass == kFlowScan) {  // uniform: one workgroup, with barriers
    scan(gl_LocalInvocationID.x);
    return;
  }
  const uint id = gl_GlobalInvocationID.x;
  if (pass == kFlowBlockStarts) {
    if (id < blocks()) blockStarts(id);
    return;
  }
  if (pass == kFlowStarts) {
    if (id < runs()) starts(id);
    return;
  }
  if (pass == kFlowOrder) {
    if (id < buckets()) order(id);
    return;
  }
  if (id >= flow.sizes.y) return;
  if (pass == kFlowBirths) {
    births(id);
  } else if (pass == kFlowScatter) {
    scatter(id);
  } else if (pass == kFlowDensity) {
    density(id);
  } else if (pass == kFlowForces) {
    forces(id);
  } else {
    store(id);
  }
}
