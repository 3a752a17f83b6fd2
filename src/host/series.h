// A run as a VTK time series for ParaView (docs/cli.md, "Series"): one XML PolyData file a
// sample, DIR/step_<step>.vtp, and DIR.pvd beside the folder, a collection naming each file
// with its simulated time. Every file appears whole or not at all, and the collection is
// rewritten after each sample, so at any moment it names exactly the samples in DIR.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lava/scene.h"
#include "lava/simulation.h"
#include "lava/state.h"

namespace lava::host {

// One sample's .vtp: the alive particles as points (float32 positions and one vertex each),
// point data velocity, speed, age, emitter, slot and, with a flow, temperature and crust;
// field data step, TimeValue (step × dt), scene_hash and state_hash. Binary appended, raw,
// little-endian, 64-bit block headers.
std::string vtpBytes(const Scene& scene, const State& state);

// FNV-1a (64 bits) of toToml(scene): the scene a sample came from.
uint64_t sceneHash(const Scene& scene);

class SeriesWriter {
 public:
  // Starts the series in `folder` (created if missing; trailing slashes dropped), one sample
  // every `every` steps, for a run whose first state is at `firstStep`. From an earlier
  // DIR.pvd it keeps the samples before `firstStep` when `resumed` (a run continued from a
  // checkpoint), none otherwise; other step_*.vtp files in the folder are removed.
  // Throws ResourceError when the folder cannot be made or written.
  SeriesWriter(std::string folder, uint64_t every, uint64_t firstStep, bool resumed);

  bool due(uint64_t step) const { return step % every_ == 0; }
  // Writes the sample of `state` (at state.step), then the collection naming it.
  void write(const Scene& scene, const State& state);
  // Writes the sample of `simulation`'s state when its step is due (a run's first state).
  void sampleIfDue(Simulation& simulation);
  // Advances `simulation` `steps` steps, in batches that stop at each step due to write its
  // sample; `run` takes each batch (by default simulation.advance).
  using Run = void (*)(Simulation& simulation, uint64_t steps);
  void advance(Simulation& simulation, uint64_t steps, Run run = nullptr);
  // DIR.pvd's path.
  const std::string& collection() const { return pvd_; }
  size_t samples() const { return entries_.size(); }

 private:
  struct Entry {
    uint64_t step;
    std::string time;  // as the collection writes it
  };
  void writeCollection() const;

  std::string folder_, name_, pvd_;
  uint64_t every_;
  // The simulation's step as the writer last saw it (its first step, a written sample's, or
  // advance()'s end): knowing it costs no read-back of the state.
  uint64_t step_;
  std::vector<Entry> entries_;
};

// "step_000000000120.vtp": a sample's file name in its folder.
std::string sampleName(uint64_t step);

}  // namespace lava::host
