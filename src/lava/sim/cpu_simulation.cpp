// The CPU reference: the model written apart from the shaders, in plain float32 C++ built
// with -ffp-contract=off, so that it and a conforming driver agree bit for bit.
#include <algorithm>
#include <cmath>
#include <thread>

#include "emission.h"
#include "lava/error.h"
#include "lava/simulation.h"
#include "model.h"
#include "reference.h"
#include "shared.h"

namespace lava {
namespace detail {

void emitParticle(const Scene& scene, size_t emitter, uint64_t serial, Particle& q) {
  const Emitter& e = scene.emitters[emitter];
  const uint32_t seed = scene.seed + static_cast<uint32_t>(emitter);
  const uint32_t lo = static_cast<uint32_t>(serial);
  const uint32_t hi = static_cast<uint32_t>(serial >> 32);
  float u[3];
  for (uint32_t c = 0; c < gpu::kVelocityComponents; ++c)
    u[c] = gpu::signedUnit(gpu::randomBits(seed, lo, hi, c));
  float dx = 0.0f, dz = 0.0f;
  for (uint32_t t = 0; t < gpu::kDiscTries; ++t) {
    const uint32_t c = gpu::kVelocityComponents + 2 * t;
    const float a = gpu::signedUnit(gpu::randomBits(seed, lo, hi, c));
    const float b = gpu::signedUnit(gpu::randomBits(seed, lo, hi, c + 1));
    if (a * a + b * b <= 1.0f) {
      dx = a;
      dz = b;
      break;
    }
  }
  q.px = e.position.x + e.radius * dx;
  q.py = e.position.y;
  q.pz = e.position.z + e.radius * dz;
  q.age = 0.0f;
  q.vx = e.velocity.x + e.spread.x * u[0];
  q.vy = e.velocity.y + e.spread.y * u[1];
  q.vz = e.velocity.z + e.spread.z * u[2];
  q.mass = e.mass;
}

void stepParticle(const Scene& s, size_t, Particle& q) {
  if (q.age < 0.0f) return;
  const float h = s.h();
  const float m = q.mass;
  float x = q.px, y = q.py, z = q.pz;
  const float vx0 = q.vx, vy0 = q.vy, vz0 = q.vz;

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
  const float age = q.age + h;

  // Ground impulse (seed eq. 7): restitution on y, retention alpha on x and z, and
  // static friction below kRestSpeed.
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
  q = {x, y, z, age, vx, vy, vz, m};
}

}  // namespace detail

namespace {

constexpr uint64_t kScheduleBatch = 4096;  // steps whose emission is planned at once

}  // namespace

CpuSimulation::CpuSimulation(const Scene& scene, unsigned threads)
    : Simulation(scene), state_(initialState(scene)), threads_(std::max(threads, 1u)) {
  detail::requireSupported(scene);
}

std::string CpuSimulation::name() const {
  return "cpu reference, " + std::to_string(threads_) + (threads_ == 1 ? " thread" : " threads");
}

void CpuSimulation::setState(const State& state) {
  checkState(scene_, state);
  state_ = state;
}

void CpuSimulation::advance(uint64_t steps) {
  const float h = scene_.h();
  std::vector<std::vector<detail::Births>> schedule(scene_.emitters.size());
  while (steps > 0) {
    const uint64_t batch = std::min(steps, kScheduleBatch);
    for (size_t k = 0; k < scene_.emitters.size(); ++k) {
      const Emitter& e = scene_.emitters[k];
      const uint64_t period = detail::burstPeriod(e, scene_.dt);
      schedule[k].clear();
      for (uint64_t i = 0; i < batch; ++i)
        schedule[k].push_back(
            detail::advanceClock(state_.clocks[k], e, h, period, state_.step + i));
    }
    state_.step += batch;

    // A block of particles goes through the steps together: their independent dependency
    // chains overlap in the CPU's pipeline, and the block stays in L1.
    auto run = [&](uint64_t begin, uint64_t end) {
      constexpr uint64_t kBlock = 32;
      for (uint64_t first = begin; first < end;) {
        const size_t k = emitterOf(scene_, first);
        const Emitter& e = scene_.emitters[k];
        const uint64_t base = scene_.firstSlot(k);
        const uint64_t n = std::min({kBlock, end - first, base + e.particles - first});
        Particle block[kBlock];
        std::copy_n(&state_.particles[first], n, block);
        for (const detail::Births& b : schedule[k]) {
          for (uint64_t j = 0; j < n; ++j) {
            const uint32_t slot = static_cast<uint32_t>(first + j - base);
            const uint32_t rel = slot >= b.head ? slot - b.head : slot + e.particles - b.head;
            if (rel < b.count) detail::emitParticle(scene_, k, b.firstSerial + rel, block[j]);
            detail::stepParticle(scene_, k, block[j]);
          }
        }
        std::copy_n(block, n, &state_.particles[first]);
        first += n;
      }
    };
    const uint64_t n = state_.particles.size();
    if (threads_ == 1 || n < 4096) {
      run(0, n);
    } else {
      std::vector<std::thread> workers;
      for (unsigned t = 0; t < threads_; ++t)
        workers.emplace_back([&, t] { run(n * t / threads_, n * (t + 1) / threads_); });
      for (std::thread& w : workers) w.join();
    }
    steps -= batch;
  }
}

}  // namespace lava
