#include "bench/bench_models.hpp"

#include <algorithm>

namespace rheo::bench {

const std::vector<BenchModel>& bench_models() {
  // Steps per repetition: about 0.2-1 s of this machine's time on the scalar reference
  // model, and at least one whole protocol run for block5 so a repetition includes a restart.
  static const std::vector<BenchModel> models = {
      {"block5", 20000},
      {"block15", 2000},
      {"lattice30", 200},
  };
  return models;
}

Scenario bench_scenario(const std::string& name) {
  if (name != "lattice30") return load_scenario(name);
  Scenario sc = load_scenario("block15");
  sc.name = name;
  sc.description = "block15 grown to a 30 x 30 x 30 particle lattice at the same 5 mm spacing";
  sc.block.nx = sc.block.ny = sc.block.nz = 30;
  const double spacing = sc.block.sx / (15 - 1);
  sc.block.sx = sc.block.sy = sc.block.sz = 29 * spacing;
  return sc;
}

ScenarioLoop::ScenarioLoop(const std::string& scenario_name, CpuPath path)
    : scenario_(bench_scenario(scenario_name)),
      model_(scenario_.build_model()),
      initial_(initial_state(model_)),
      period_(scenario_.default_steps()) {
  if (path.fast) {
    fast_ = std::make_unique<fast::FastSimulator>(model_, scenario_.options, path.threads);
  } else {
    scalar_ = std::make_unique<Simulator>(model_, scenario_.options);
  }
}

void ScenarioLoop::restart() {
  if (fast_) {
    fast_->set_state(initial_);
  } else {
    scalar_->mutable_state() = initial_;
  }
  step_ = 0;
}

double ScenarioLoop::step() {
  if (at_end()) restart();
  ++step_;
  ++total_;
  const double z = scenario_.plate_z(model_, step_);
  return (fast_ ? fast_->step(z) : scalar_->step(z)).plate_force_N;
}

double ScenarioLoop::run(int steps) {
  if (at_end()) restart();
  const long long n = std::min<long long>(steps, period_ - step_);
  plate_z_.clear();
  for (long long i = 1; i <= n; ++i) plate_z_.push_back(scenario_.plate_z(model_, step_ + i));
  step_ += n;
  total_ += n;
  if (fast_) return fast_->run(plate_z_).back().plate_force_N;
  double force = 0.0;
  for (double z : plate_z_) force = scalar_->step(z).plate_force_N;
  return force;
}

}  // namespace rheo::bench
