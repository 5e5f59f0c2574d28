#include "bench/bench_models.hpp"

namespace rheo::bench {

const std::vector<BenchModel>& bench_models() {
  // Steps per repetition: about 0.2-1 s of this machine's time on the reference model, and
  // at least one whole protocol run for block5 so a repetition includes a restart.
  static const std::vector<BenchModel> models = {
      {"block5", 20000},
      {"block15", 2000},
  };
  return models;
}

ScenarioLoop::ScenarioLoop(const std::string& scenario_name)
    : scenario_(load_scenario(scenario_name)),
      model_(scenario_.build_model()),
      sim_(model_, scenario_.options),
      initial_(sim_.state()),
      period_(scenario_.default_steps()) {}

void ScenarioLoop::restart() {
  sim_.mutable_state() = initial_;
  step_ = 0;
}

double ScenarioLoop::step() {
  if (at_end()) restart();
  ++step_;
  ++total_;
  return sim_.step(scenario_.plate_z(model_, step_)).plate_force_N;
}

}  // namespace rheo::bench
