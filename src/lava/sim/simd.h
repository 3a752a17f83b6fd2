// The cpu-simd kernel: reference.cpp's model on SIMD lanes (Highway, the widest target the
// CPU runs, chosen at run time), particle j of a block in lane j. Every lane computes the
// operations of Reference::step in the same order, without fused multiply-add, so its
// bytes equal the reference's; emission is the reference's own, one particle at a time.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "emission.h"
#include "lava/state.h"
#include "reference.h"

namespace lava::detail {

// Particles one kernel call holds at once (structure of arrays, in L1).
constexpr size_t kSimdBlock = 128;

// As Reference::run, for count <= kSimdBlock slots.
void simdRun(const Reference& reference, size_t emitter, const std::vector<Births>& schedule,
             uint32_t first, Particle* slots, size_t count);

// The compute ceiling: `steps` steps of emitter 0's particles over one block of
// kSimdBlock that never leaves L1, through the kernel's own loop (simdRun, or
// Reference::run when `scalar`) with no births; returns the updates done.
uint64_t stepKernelOnly(const Reference& reference, Particle* block, uint64_t steps, bool scalar);

// "AVX3 (512-bit, 16 lanes)": the instruction set simdRun uses on this CPU.
std::string simdTarget();
// The instruction sets compiled in and supported by this CPU, best first; and a choice of
// one of them for every simdRun ("" for the best). Lava dispatches to it itself: Highway's
// own target selection, which a host may use, is never changed.
std::vector<std::string> simdTargets();
void useSimdTarget(const std::string& name);

}  // namespace lava::detail
