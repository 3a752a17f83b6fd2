#include "cpu_simulator.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace lava {
namespace {

constexpr uint64_t kScheduleBatch = 4096;  // steps whose emission is planned at once

void emit(const Scene& s, uint64_t serial, Particle& q) {
  const uint32_t lo = static_cast<uint32_t>(serial);
  const uint32_t hi = static_cast<uint32_t>(serial >> 32);
  float u[3];
  for (uint32_t c = 0; c < gpu::kVelocityComponents; ++c)
    u[c] = gpu::signedUnit(gpu::randomBits(s.seed, lo, hi, c));
  float dx = 0.0f, dz = 0.0f;
  for (uint32_t t = 0; t < gpu::kDiscTries; ++t) {
    const uint32_t c = gpu::kVelocityComponents + 2 * t;
    float a = gpu::signedUnit(gpu::randomBits(s.seed, lo, hi, c));
    float b = gpu::signedUnit(gpu::randomBits(s.seed, lo, hi, c + 1));
    if (a * a + b * b <= 1.0f) {
      dx = a;
      dz = b;
      break;
    }
  }
  q.posAge = {s.emitter.x + s.emitterRadius * dx, s.emitter.y, s.emitter.z + s.emitterRadius * dz,
              0.0f};
  q.velMass = {s.velocity.x + s.spread.x * u[0], s.velocity.y + s.spread.y * u[1],
               s.velocity.z + s.spread.z * u[2], s.mass};
}

}  // namespace

SimState initialState(const Scene& scene) {
  SimState state;
  state.particles.assign(scene.particles,
                         Particle{{0.0f, 0.0f, 0.0f, -1.0f}, {0.0f, 0.0f, 0.0f, 0.0f}});
  return state;
}

void stepParticle(const Scene& s, Particle& q, bool born, uint64_t serial) {
  if (born) emit(s, serial, q);
  float age = q.posAge.w;
  if (age < 0.0f) return;
  const float h = s.dt;
  const float m = q.velMass.w;
  float x = q.posAge.x, y = q.posAge.y, z = q.posAge.z;
  const float vx0 = q.velMass.x, vy0 = q.velMass.y, vz0 = q.velMass.z;

  // Explicit Euler (seed eqs. 4-5): position with the old velocity first.
  x = x + h * vx0;
  y = y + h * vy0;
  z = z + h * vz0;
  const float fx = s.wind.x - s.drag * vx0;
  const float fy = (s.wind.y - m * s.gravity) - s.drag * vy0;
  const float fz = s.wind.z - s.drag * vz0;
  const float hm = h / m;
  float vx = vx0 + hm * fx;
  float vy = vy0 + hm * fy;
  float vz = vz0 + hm * fz;
  age = age + h;

  // Ground impulse (seed eq. 7): restitution on y, retention alpha on x and z, and
  // static friction below kRestSpeed, which also keeps denormals out of the state.
  if (y < 0.0f) {
    y = 0.0f;
    if (vy < 0.0f) {
      vx = s.friction * vx;
      vz = s.friction * vz;
      vy = -(s.restitution * vy);
      if (std::fabs(vx) < gpu::kRestSpeed) vx = 0.0f;
      if (std::fabs(vz) < gpu::kRestSpeed) vz = 0.0f;
    }
  }
  q.posAge = {x, y, z, age};
  q.velMass = {vx, vy, vz, m};
}

CpuSimulator::CpuSimulator(const Scene& scene, unsigned threads)
    : Simulator(scene), state_(initialState(scene)) {
  threads_ = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
}

void CpuSimulator::runRange(const std::vector<EmitStep>& schedule, size_t begin, size_t end) {
  // A block of particles goes through the steps together: their independent dependency
  // chains overlap in the CPU's pipeline, and the block stays in L1.
  constexpr size_t kBlock = 32;
  const uint32_t capacity = scene_.particles;
  for (size_t first = begin; first < end; first += kBlock) {
    const size_t n = std::min(kBlock, end - first);
    Particle block[kBlock];
    std::copy_n(&state_.particles[first], n, block);
    for (const EmitStep& e : schedule) {
      for (size_t k = 0; k < n; ++k) {
        const uint32_t slot = static_cast<uint32_t>(first + k);
        const uint32_t rel = slot >= e.head ? slot - e.head : slot + capacity - e.head;
        stepParticle(scene_, block[k], rel < e.count, e.firstSerial + rel);
      }
    }
    std::copy_n(block, n, &state_.particles[first]);
  }
}

void CpuSimulator::advance(uint64_t steps) {
  std::vector<EmitStep> schedule;
  while (steps > 0) {
    const uint64_t batch = std::min(steps, kScheduleBatch);
    schedule.clear();
    for (uint64_t k = 0; k < batch; ++k)
      schedule.push_back(state_.clock.advance(scene_.rate, scene_.dt, scene_.particles));
    const size_t n = state_.particles.size();
    if (threads_ == 1 || n < 4096) {
      runRange(schedule, 0, n);
    } else {
      std::vector<std::thread> workers;
      for (unsigned t = 0; t < threads_; ++t)
        workers.emplace_back(
            [&, t] { runRange(schedule, n * t / threads_, n * (t + 1) / threads_); });
      for (std::thread& w : workers) w.join();
    }
    steps -= batch;
  }
}

}  // namespace lava
