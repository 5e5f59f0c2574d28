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

#include <string>
#include <vector>

#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::bench {

struct BenchModel {
  std::string scenario;  // built-in scenario name
  long long steps = 0;   // steps one benchmark repetition times
};

// The benchmark models and how many steps each benchmark repetition runs.
const std::vector<BenchModel>& bench_models();

// Steps a scenario's protocol from rest, over and over (see above).
class ScenarioLoop {
 public:
  explicit ScenarioLoop(const std::string& scenario_name);

  // One step of the scenario; restarts from rest first when the protocol has ended.
  // Returns the plate force [N]. Throws rheo::Error on a numerical failure.
  double step();

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
  Simulator sim_;
  State initial_;
  long long period_ = 0;  // steps of one protocol run
  long long step_ = 0;    // steps since the last restart
  long long total_ = 0;   // steps since construction
};

}  // namespace rheo::bench
