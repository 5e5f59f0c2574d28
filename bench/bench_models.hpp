// The models the speed benchmarks run, shared with the test that runs each of them for ten
// times a benchmark's steps (bench_models_test), so a benchmark can never hit a numerical
// failure that no test has seen.
//
// A benchmark model is a built-in scenario run exactly as `rheo simulate` runs it (its
// mesh, material, dt and plate protocol), with one difference: when the scenario's
// protocol has run its course the object is put back at rest and the protocol starts again.
// The three-element edge has no long-term stiffness, so any object made of it sags under
// its own weight without end (block5: ~0.05 mm/s) and, left alone for long enough, folds
// through itself; restarting keeps every timed step inside the protocol the scenario tests
// cover, whatever number of steps the benchmark library chooses.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/fast/fast_simulator.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::bench {

struct BenchModel {
  std::string scenario;  // built-in scenario name
  long long steps = 0;   // steps one benchmark repetition times
};

// The benchmark models and how many steps each benchmark repetition runs: the built-in
// block5 and block15, and lattice30, block15 grown to 30 x 30 x 30 particles (same
// spacing, material, step and protocol; 27,000 particles).
const std::vector<BenchModel>& bench_models();

// A benchmark model's scenario by name (a built-in one, or lattice30).
Scenario bench_scenario(const std::string& name);

// Which CPU path steps the model: the scalar reference (rheo::Simulator) or the fast path
// (rheo::fast::FastSimulator) with a thread count.
struct CpuPath {
  bool fast = false;
  int threads = 1;
};

// Steps a scenario's protocol from rest, over and over (see above).
class ScenarioLoop {
 public:
  explicit ScenarioLoop(const std::string& scenario_name, CpuPath path = {});

  // One step of the scenario; restarts from rest first when the protocol has ended.
  // Returns the plate force [N]. Throws rheo::Error on a numerical failure.
  double step();
  // `steps` steps up to the protocol's end (fewer when it ends first), in one call of the
  // fast path's run() as the backends make it; the last plate force.
  double run(int steps);

  // True when the next step() restarts from rest (a benchmark pauses its timer for it).
  bool at_end() const { return step_ >= period_; }
  // Puts the object back at rest at t = 0.
  void restart();

  const Scenario& scenario() const { return scenario_; }
  const Model& model() const { return model_; }
  long long period_steps() const { return period_; }
  long long steps_done() const { return total_; }

 private:
  Scenario scenario_;
  Model model_;
  std::unique_ptr<Simulator> scalar_;
  std::unique_ptr<fast::FastSimulator> fast_;
  State initial_;
  long long period_ = 0;  // steps of one protocol run
  long long step_ = 0;    // steps since the last restart
  long long total_ = 0;   // steps since construction
  std::vector<double> plate_z_;  // run()'s plate heights
};

}  // namespace rheo::bench
