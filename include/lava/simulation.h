// The two backends behind one face: the GPU simulation (compute shaders, recorded into the
// host's command buffers) and the CPU reference (plain float32 C++, the oracle). Given the
// same Scene and State they compute the same bytes on a conforming driver.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "device.h"
#include "export.h"
#include "scene.h"
#include "state.h"

namespace lava {

// What both backends offer: blocking calls for tools, tests and scripts.
class LAVA_API Simulation {
 public:
  virtual ~Simulation();
  const Scene& scene() const { return scene_; }
  // Replaces the parameters from the next step on; the emitters and their capacities must
  // stay the same (InvalidArgument otherwise). Not blocking: it records, submits and waits
  // for nothing (the GPU's builds the pipelines the new scene needs, if new), so a host may
  // call it from its UI between frames.
  virtual void setScene(const Scene& scene);
  // Blocking: runs `steps` steps.
  virtual void advance(uint64_t steps) = 0;
  // Blocking: the current state.
  virtual State state() = 0;
  // Blocking: replaces the state (checkState() first).
  virtual void setState(const State& state) = 0;
  // "gpu (llvmpipe ...)", "cpu reference, 2 threads", "cpu-simd AVX2 (256-bit, 8 lanes), ...".
  virtual std::string name() const = 0;

 protected:
  explicit Simulation(const Scene& scene);
  Scene scene_;
};

// How the CPU backend computes a step. Both give the same bytes.
enum class CpuKernel {
  Reference,  // the oracle: plain float32 C++, one particle at a time
  Simd,       // cpu-simd: the same operations on SIMD lanes (the widest the CPU runs)
};

// The instruction set named `target` (one of cpuSimdTargets()) on this CPU, in words:
// "AVX2 (256-bit, 8 lanes)"; "" names the best, which CpuKernel::Simd uses unless a
// simulation names another. InvalidArgument naming "simd-target" for another name.
LAVA_API std::string cpuSimdTarget(const std::string& target = "");
// The instruction sets it can use here (compiled in and run by this CPU), best first:
// "AVX3", "AVX2", "SSE4", ... Every one computes the same bytes. A simulation chooses one
// (CpuSimulation's simdTarget); Lava dispatches to it itself, so Highway's own target
// selection, which the host may use too, is left alone, and no choice is process-wide.
LAVA_API std::vector<std::string> cpuSimdTargets();

// The CPU backend: the reference written apart from the shaders, or its SIMD twin.
// Thread safety: one thread at a time per object; distinct objects are independent (with
// threads > 1, advance() runs its own workers and joins them before it returns).
class LAVA_API CpuSimulation final : public Simulation {
 public:
  // `threads` workers split the particles (1: the calling thread only, no thread created).
  // `simdTarget`: for CpuKernel::Simd, one of cpuSimdTargets() ("": the best);
  // InvalidArgument naming "simd-target" otherwise.
  explicit CpuSimulation(const Scene& scene, unsigned threads = 1,
                         CpuKernel kernel = CpuKernel::Reference,
                         const std::string& simdTarget = "");
  ~CpuSimulation() override;
  CpuSimulation(CpuSimulation&&) noexcept;
  CpuSimulation& operator=(CpuSimulation&&) noexcept;
  void advance(uint64_t steps) override;
  void setScene(const Scene& scene) override;
  State state() override { return state_; }
  void setState(const State& state) override;
  std::string name() const override;
  unsigned threads() const { return threads_; }
  CpuKernel kernel() const { return kernel_; }
  // CpuKernel::Simd's instruction set, "AVX2 (256-bit, 8 lanes)"; "" for the reference.
  std::string simdTarget() const;
  // The state in place (no copy), valid until the next call that changes it.
  const State& view() const { return state_; }

 private:
  State state_;
  unsigned threads_;
  CpuKernel kernel_;
  int64_t simdTarget_;  // Highway's target bit (0: the best)
  // The scene's reference and the flow's stepper, kept from one advance() to the next (a host
  // that steps a frame at a time would otherwise start the flow's threads and allocate its
  // buffers every frame); a new scene makes them again.
  struct Steppers;
  std::unique_ptr<Steppers> steppers_;
};

struct GpuSimulationOptions {
  uint32_t maxStepsPerFrame = 2048;  // most steps one update() may plan
  uint32_t stepsPerDispatch = 256;   // 1..256 steps fused per dispatch (1: memory-bound)
  // Particles one chunk (binding, texel view, dispatch) holds: 0 for as many as the device
  // allows (Device::particlesPerChunk()), else at most this many, in whole workgroups of 64.
  uint32_t maxParticlesPerChunk = 0;
  // The blocking helpers' bound on one submission: at most this many particle-steps (the
  // scene's slots x steps; one step at least), 2^26 by default, so that no submission runs
  // near the watchdogs of desktop drivers (2 s and more). At least 1.
  uint64_t maxParticleStepsPerSubmission = uint64_t{1} << 26;
};

// Particles [first, first + count) of the state, in `buffer` from offset 0, 32 bytes each
// (Particle), also viewed as RGBA32F texels (posAge, velMass per particle) by `texels`.
struct ParticleChunk {
  uint64_t first;
  uint32_t count;
  VkBuffer buffer;
  VkBufferView texels;
};

// The compute-shader backend. A frame in a host application:
//
//   sim.update(frame, steps);            // CPU: plan the emission, stage the schedule
//   sim.recordSimulate(cmd, frame);      // record the steps into the host's command buffer
//   ... draw with LineRenderer, submit, present ...
//
// `frame` is the frame slot, below Device::framesInFlight(): the index of the host's fence
// that guards the frame, not the swapchain image's (see Device::setFramesInFlight).
// update(frame) may be called once the host's previous submission that used `frame` has
// finished.
// Thread safety: one thread at a time per object (const calls from any thread while no
// other call runs); distinct objects on one Device on distinct threads, except the
// blocking helpers (see Device).
class LAVA_API GpuSimulation final : public Simulation {
 public:
  GpuSimulation(Device& device, const Scene& scene, const GpuSimulationOptions& options = {});
  ~GpuSimulation() override;
  GpuSimulation(const GpuSimulation&) = delete;
  GpuSimulation& operator=(const GpuSimulation&) = delete;

  // CPU side of a frame: advances the emission clocks by `steps` (0..maxStepsPerFrame) and
  // writes their schedule and the scene's parameters into frame slot `frame`. Every
  // update() must be followed by one recordSimulate(frame) that the host submits; a second
  // update(frame) before it throws InvalidArgument ("frame") and plans nothing. The
  // first update() compiles the step's second pipeline (the one for workgroups no birth
  // lands on), so that a simulation that never steps does not pay for it.
  void update(uint32_t frame, uint32_t steps);
  // Records the steps of the last update(frame), once: a second call before the next
  // update(frame) records nothing (and nothing when it planned none).
  // Before: a barrier after every earlier use of the particle buffers on the queue
  // (writes by COMPUTE_SHADER or TRANSFER; reads by VERTEX_SHADER, FRAGMENT_SHADER,
  // COMPUTE_SHADER or TRANSFER), so it may follow any Lava call and any such read.
  // After: the particle buffers are written by VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT with
  // VK_ACCESS_SHADER_WRITE_BIT; a reader needs a barrier from there (LineRenderer's
  // recordPrepare() records it).
  // Records only: no submission or wait. On a device without VK_KHR_push_descriptor it
  // writes the slot's descriptor sets (allocated from Lava's own pool by the first
  // recordings of the slot, then reused), so a command buffer it recorded into cannot be
  // submitted again once the slot is recorded anew.
  void recordSimulate(VkCommandBuffer commands, uint32_t frame);
  // The set-up of the particle buffers (every slot unborn: an inline update and copies),
  // recorded once, when still due: the first recordSimulate(), LineRenderer's first
  // recordPrepare() and the first blocking call record it themselves; call it to choose
  // where. After: TRANSFER writes made visible to COMPUTE_SHADER, VERTEX_SHADER,
  // FRAGMENT_SHADER and TRANSFER access. Records only; const because the particles it
  // writes are the state the simulation already reports.
  void recordInit(VkCommandBuffer commands) const;

  // Blocking helpers. They submit to the device's queue and wait for that submission;
  // call them when no command buffer with this simulation's work is pending submission.
  // advance() splits its steps into submissions of at most
  // GpuSimulationOptions::maxParticleStepsPerSubmission particle-steps each.
  // Nothing else in the class submits or waits: the constructor and the destructor only
  // create and destroy (destroy it once the host's last submission that used it has
  // finished).
  void advance(uint64_t steps) override;
  // advance() that returns the GPU time the steps took (timestamp queries), in seconds.
  double advanceTimed(uint64_t steps);
  State state() override;
  void setState(const State& state) override;

  // Not blocking (see Simulation): records, submits and waits for nothing; the frames
  // recorded after it step the new scene (docs/library.md, "Live edits").
  void setScene(const Scene& scene) override;
  std::string name() const override;

  const std::vector<ParticleChunk>& chunks() const;
  // The flow's own particles, one per flow slot (the flow emitters' rings one after
  // another; their copies in chunks() are made after each recorded batch of steps), and
  // beside each its temperature (float, K) and crust flag (uint32, 1: crust): what the
  // renderers draw molten rock from. Null and 0 slots for a scene without flow emitters.
  struct FlowBuffers {
    VkBuffer particles = VK_NULL_HANDLE;
    VkBuffer heat = VK_NULL_HANDLE;
    uint32_t slots = 0;
  };
  FlowBuffers flowBuffers() const;
  const GpuSimulationOptions& options() const;
  // The host's side of the state, without a read-back: each emitter's clock and the steps
  // planned so far (by update() and the blocking helpers).
  const std::vector<EmitterClock>& clocks() const;
  uint64_t step() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace lava
