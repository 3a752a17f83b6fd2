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
#include "internal.h"

namespace lava::detail {

// Particles one kernel call holds at once (structure of arrays, in L1).
constexpr size_t kSimdBlock = 128;

// An instruction set of this CPU, as Highway's target bit; 0: the best.
using SimdTarget = int64_t;

// As Reference::run, for count <= kSimdBlock slots, on `target`.
void simdRun(const Reference& reference, SimdTarget target, size_t emitter,
             const std::vector<Births>& schedule, uint32_t first, Particle* slots, size_t count);

// The compute ceiling: `steps` steps of emitter 0's particles over one block of
// kSimdBlock that never leaves L1, through the kernel's own loop (simdRun, or
// Reference::run when `scalar`) with no births; returns the updates done.
LAVA_INTERNAL uint64_t stepKernelOnly(const Reference& reference, Particle* block, uint64_t steps, bool scalar,
                        SimdTarget target = 0);

// "AVX3 (512-bit, 16 lanes)": the instruction set `target` names on this CPU.
std::string simdTarget(SimdTarget target = 0);
// The instruction sets compiled in and supported by this CPU, best first; and the one
// named `name` ("" for the best; InvalidArgument naming "simd-target" for another name).
// Lava dispatches to it itself: Highway's own target selection, which a host may use, is
// never changed, and no choice is kept anywhere but where the caller keeps it.
std::vector<std::string> simdTargets();
LAVA_INTERNAL SimdTarget simdTargetNamed(const std::string& name);

}  // namespace lava::detail
