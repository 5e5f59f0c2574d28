// Shared by the cosimulation tests of the edge's optional parts (arm_cosim_test.cpp,
// damper_cosim_test.cpp): how much a part changes the plate force, and the printed figures.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "host/cosim/cosim.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::cosim_test {

struct ForceEffect {
  double max_diff_N = 0.0;  // largest |fixed-point force - force without the part|
  double peak_N = 0.0;      // peak |fixed-point force|
};

// The cosimulation's fixed-point plate force against a double reference of `without` (the
// scenario's model lacking the part) under the scenario's protocol, over the run's steps.
inline ForceEffect force_effect(const Scenario& scenario, const Model& without,
                                const cosim::CosimResult& r) {
  Simulator sim(without, scenario.options);
  ForceEffect e;
  for (long n = 0; n < r.steps; ++n) {
    const double t = double(n + 1) * scenario.options.dt;
    const double f =
        sim.step(without.height - scenario.protocol.displacement_mm(t) * 1e-3).plate_force_N;
    e.max_diff_N = std::max(e.max_diff_N, std::fabs(r.force_fixed_N[n] - f));
    e.peak_N = std::max(e.peak_N, std::fabs(r.force_fixed_N[n]));
  }
  return e;
}

// Prints the run's figures under `label` (the part's effect named `part`) and records the
// errors as test properties.
inline void report(const char* label, const char* part, const cosim::CosimResult& r,
                   const ForceEffect& e) {
  std::printf(
      "%s cosim: %ld steps, max_pos_err_rel %.3g, max_force_err_rel %.3g, %s effect %.3g N "
      "of peak %.3g N, cycles/step %.1f (formula %ld)\n",
      label, r.steps, r.max_pos_err_rel, r.max_force_err_rel, part, e.max_diff_N, e.peak_N,
      r.cycles_per_step_measured, r.cycles_per_step_formula);
  ::testing::Test::RecordProperty("max_pos_err_rel", std::to_string(r.max_pos_err_rel));
  ::testing::Test::RecordProperty("max_force_err_rel", std::to_string(r.max_force_err_rel));
}

}  // namespace rheo::cosim_test
