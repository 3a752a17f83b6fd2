// The model's operations shared by step.comp and flow.comp (docs/model.md): emission,
// forces, the colliders' responses and the cone's 1/sqrt, every float `precise`. The includer
// declares the scene's uniform block `scene` and the constants kForces, kForceKinds,
// kColliders first.
#ifndef LAVA_MODEL_GLSL
#define LAVA_MODEL_GLSL

// What every particle's steps need of the scene, read once per dispatch.
struct World {
  float h;            // step (s)
  float drag;         // N s/m
  float restitution;  // the ground's
  float friction;
  vec3 wind;          // N
};

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

// The ground y = 0: restitution on y, retention and static friction on x and z. Returns
// whether it moved the particle.
bool ground(float restitution, float friction, inout precise vec3 x, inout precise vec3 v) {
  if (!(x.y < 0.0)) return false;
  x.y = 0.0;
  if (v.y < 0.0) {
    v.x = friction * v.x;
    v.z = friction * v.z;
    v.y = -(restitution * v.y);
    if (abs(v.x) < kRestSpeed) v.x = 0.0;
    if (abs(v.z) < kRestSpeed) v.z = 0.0;
    flush(v);
  }
  return true;
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
bool cone(const ColliderParams c, inout precise vec3 x, inout precise vec3 v) {
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
      return true;
    }
  }
  return false;
}

// Collider c of kind `type`: a particle inside is put on its surface and responds. Returns
// whether it moved the particle.
bool collide(const ColliderParams c, uint type, inout precise vec3 x, inout precise vec3 v) {
  if (type == kPlane) {
    precise vec3 n = c.shape.xyz;
    precise vec3 r = x - c.position.xyz;
    precise float dist = (r.x * n.x + r.y * n.y) + r.z * n.z;
    if (!(dist < 0.0)) return false;
    x = x - dist * n;
    respond(v, n, c.material.x, c.material.y);
    flush(v);
    return true;
  }
  if (type == kSphere) {
    precise vec3 d = x - c.position.xyz;
    precise float q = (d.x * d.x + d.y * d.y) + d.z * d.z;
    if (!(q < c.shape.y)) return false;
    precise vec3 n = vec3(0.0, 1.0, 0.0);
    if (q != 0.0) {
      precise float s = sqrt(q);  // the model's one square root and division
      n = vec3(d.x / s, d.y / s, d.z / s);
    }
    x = c.position.xyz + c.shape.x * n;
    respond(v, n, c.material.x, c.material.y);
    flush(v);
    return true;
  }
  if (type == kBox) {
    precise vec3 d = x - c.position.xyz;
    const vec3 e = c.shape.xyz;
    // Standing on the ground (its bottom at or below it): the ground closes the bottom
    // face, so the box holds from the ground up and its bottom is no exit.
    const bool standing = c.position.y <= e.y;
    // Inside: strictly between the faces where a particle is put out (centre -+ size), so
    // that one put on a face is outside there; |x - centre| < size can round inside.
    precise vec3 lo = c.position.xyz - e, hi = c.position.xyz + e;
    const bool below = x.y < hi.y && (standing || x.y > lo.y);
    if (!(x.x > lo.x && x.x < hi.x && below && x.z > lo.z && x.z < hi.z)) return false;
    precise vec3 gap = e - abs(d);
    if (standing) gap.y = e.y - d.y;
    uint j = 0u;
    if (gap.y < gap.x) j = 1u;
    if (gap.z < (j == 0u ? gap.x : gap.y)) j = 2u;
    precise float sigma = (j == 1u && standing) || d[j] >= 0.0 ? 1.0 : -1.0;
    x[j] = c.position[j] + sigma * e[j];
    precise vec3 n = vec3(0.0);
    n[j] = sigma;
    respond(v, n, c.material.x, c.material.y);
    flush(v);
    return true;
  }
  return cone(c, x, v);
}

// Collider c as the particles of this pass meet it: a flow particle's restitution is the
// flow's own (`restitution` >= 0), a spark's the collider's (`restitution` < 0).
ColliderParams colliderAt(uint c, float restitution) {
  ColliderParams k = scene.colliders[c];
  if (restitution >= 0.0) k.material.x = restitution;
  return k;
}

// One solid's visit in contact: a move restarts the count of solids that found the particle
// outside, after which all but the mover must. Returns whether contact is done.
bool visited(bool moved, inout uint clear, inout uint need, inout bool touched) {
  if (moved) {
    touched = true;
    clear = 0u;
    need = kColliders;
  } else {
    ++clear;
  }
  return clear >= need;
}

// docs/model.md "Contact": the ground, then the colliders in the scene's order, round and
// round until every solid but the last to move the particle has found it outside since
// then; at most kContactRounds rounds. Returns false when the particle is still unresolved
// after them (the caller then takes back its start of step, or lets it die).
bool contact(float groundRestitution, float friction, float restitution,
             inout precise vec3 x, inout precise vec3 v, out bool touched) {
  uint clear = 0u, need = kColliders + 1u;  // solids in a row that found it outside; how many
  touched = false;
  for (uint r = 0u; r < kContactRounds; ++r) {
    if (visited(ground(groundRestitution, friction, x, v), clear, need, touched)) return true;
    [[unroll]] for (uint c = 0u; c < kColliders; ++c) {
      const uint kind = (kColliderKinds >> (2u * c)) & 3u;
      if (visited(collide(colliderAt(c, restitution), kind, x, v), clear, need, touched))
        return true;
    }
  }
  return false;
}

// Whether x lies inside the ground or a collider.
bool insideASolid(precise vec3 x) {
  bool inside = x.y < 0.0;
  [[unroll]] for (uint c = 0u; c < kColliders; ++c) {
    precise vec3 at = x, v = vec3(0.0);
    inside = collide(scene.colliders[c], (kColliderKinds >> (2u * c)) & 3u, at, v) || inside;
  }
  return inside;
}

// Contact for a particle that started the step at x0. An unresolved particle takes back x0
// with v = 0; when x0 is inside a solid too, it dies (returns true; x = v = 0).
bool contactFrom(precise vec3 x0, float groundRestitution, float friction, float restitution,
                 inout precise vec3 x, inout precise vec3 v, out bool touched) {
  if (contact(groundRestitution, friction, restitution, x, v, touched)) return false;
  v = vec3(0.0);
  const bool lost = insideASolid(x0);
  x = lost ? vec3(0.0) : x0;
  return lost;
}

// Whether any component is NaN or infinite (all exponent bits set): integer operations,
// which no float mode of a driver can change.
bool nonFinite(precise vec3 x, precise vec3 v) {
  const uvec3 all = uvec3(0x7f800000u);
  return any(equal(floatBitsToUint(x) & all, all)) || any(equal(floatBitsToUint(v) & all, all));
}

#endif  // LAVA_MODEL_GLSL
