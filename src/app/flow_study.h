// `lava study --flow CASE`: the flow against published solutions (docs/flow.md, "Against
// published solutions"), each a scene built here and a measurement taken the same way in the
// docs and the tests.
#pragma once
#include <string>
#include <vector>

#include "lava/scene.h"

namespace lava::app {

// The cases, by name: nusselt, dam-break, huppert-slope, huppert-spread, at-rest.
extern const char* const kFlowCases;

struct FlowStudyOptions {
  std::string name;        // a case
  double viscosity = 0.0;  // m^2/s; 0: the case's own
  double dt = 0.001;       // s
  double seconds = 0.0;    // simulated time; 0: the case's own
  unsigned threads = 2;    // of the CPU reference
  FlowSolver solver = FlowSolver::Implicit;  // the method measured
};

// One look at the run: at time t, the measured quantity and the published one.
struct FlowSample {
  double t, measured, published;
};

struct FlowStudy {
  std::string quantity;   // what is measured, with its unit
  std::string reference;  // the published solution, in words
  std::vector<FlowSample> samples;
  // The verdict: the largest |measured / published - 1| over the samples that count (or, for
  // at-rest, the fastest speed at the end), against the tolerance.
  double deviation = 0.0, tolerance = 0.0;
  bool holds() const { return deviation <= tolerance; }
};

// Runs the case on the CPU reference. UsageError-like std::invalid_argument for an unknown
// name (the message lists kFlowCases).
FlowStudy studyFlow(const FlowStudyOptions& options);

}  // namespace lava::app
