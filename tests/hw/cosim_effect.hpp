// Shared by the cosimulation tests of the edge's optional parts (arm_cosim_test.cpp,
// damper_cosim_test.cpp, hardening_cosim_test.cpp, every_effect_cosim_test.cpp,
// volume_cosim_test.cpp, whole_protocol_cosim_test.cpp): the run and what each must show, how
// much a part changes the plate force, the printed figures, and the every-effect and
// every-feature checks that run over a time-compressed protocol by default and over the whole
// protocol under the opt-in label `long`.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::cosim_test {

// Runs `steps` of `scenario` on the one-lane RTL core against the bit-true model (state
// compared every 5 steps) and checks what every feature's cosimulation must show: the core
// of `element` was chosen, bit-exact over all steps, nothing dropped, fixed point within the
// given bounds of the double reference, and the measured cycles per step equal to the
// formula with the element's TEM drain.
inline cosim::CosimResult expect_exact_feature_cosim(const Scenario& scenario,
                                                     const hls::EdgeElement& element, long steps,
                                                     double max_pos_err_rel,
                                                     double max_force_err_rel) {
  cosim::CosimOptions opt;
  opt.steps = steps;
  opt.lanes = 1;
  opt.compare_every = 5;
  const cosim::CosimResult r = cosim::run_cosim(scenario, opt);
  EXPECT_EQ(r.element, element.name);
  EXPECT_EQ(r.mismatches, 0) << (r.first.empty() ? "" : r.first.front().describe());
  EXPECT_EQ(r.steps, steps);
  // After the last step the whole state, the edges' Voigt lengths and arm extensions too.
  EXPECT_GE(r.final_state_words, 6L * r.particles + r.edges);
  EXPECT_TRUE(r.dropped_features.empty())
      << "dropped: " << (r.dropped_features.empty() ? "" : r.dropped_features.front());
  EXPECT_LE(r.max_pos_err_rel, max_pos_err_rel);
  EXPECT_LE(r.max_force_err_rel, max_force_err_rel);
  EXPECT_EQ(r.cycles_per_step_formula,
            driver::cycles_per_step_formula(r.edge_rows, r.particles, 1, element));
  EXPECT_DOUBLE_EQ(r.cycles_per_step_measured, double(r.cycles_per_step_formula));
  return r;
}

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

// Fixed point against the double reference: the every-effect and every-feature bounds.
constexpr double kEveryMaxPositionErrorRel = 2e-5;
constexpr double kEveryMaxForceErrorRel = 5e-4;
// Each part must matter: without it the double model's force differs from the fixed-point
// force by far more than the quantisation bound.
constexpr double kEveryMinEffectRel = 0.02;

// The whole shipped protocol runs 10,000 steps on a one-lane core, minutes of Verilator time.
// Every protocol knot and the run length divided by `factor` keeps every phase (push, hold,
// release, rest) at a `factor` times faster plate: the default suite runs that, the whole
// protocol runs under the opt-in label `long` (whole_protocol_cosim_test.cpp).
inline Scenario time_compressed(Scenario s, double factor) {
  for (double& t : s.protocol.t) t /= factor;
  s.duration_s /= factor;
  return s;
}

// block5 with the series damper, strain hardening and the eight-arm spectrum
// (data/scenarios/block5_every_edge_effect.json) over all of `scenario`'s protocol: bit-exact
// on the every-effect core, its longer drain in the cycle count, and each effect changing the
// plate force by more than kEveryMinEffectRel of its peak.
inline void expect_every_edge_effect(const Scenario& scenario) {
  const Model model = scenario.build_model();
  ASSERT_EQ(scenario.block.material.spectrum_arms, 8);
  ASSERT_TRUE(scenario.block.material.nonlinear);
  ASSERT_GT(scenario.block.material.hardening, 0.0);
  EXPECT_EQ(driver::edge_element_for(model), hls::kThreeElementEveryEffect);

  const cosim::CosimResult r = expect_exact_feature_cosim(
      scenario, hls::kThreeElementEveryEffect, scenario.default_steps(),
      kEveryMaxPositionErrorRel, kEveryMaxForceErrorRel);
  EXPECT_EQ(r.cycles_per_step_formula,
            driver::cycles_per_step_formula(r.edge_rows, r.particles, 1) + hls::kHardDamperTemExtra);

  struct Without {
    const char* effect;
    void (*remove)(EdgeMaterial&);
  };
  const Without parts[] = {
      {"damper", [](EdgeMaterial& m) { m.nonlinear = false; }},
      {"hardening", [](EdgeMaterial& m) { m.hardening = 0.0; }},
      {"spectrum", [](EdgeMaterial& m) { m.spectrum_arms = 0; }},
  };
  for (const Without& w : parts) {
    Model without = model;
    for (EdgeMaterial& m : without.materials) w.remove(m);
    const ForceEffect e = force_effect(scenario, without, r);
    EXPECT_GE(e.max_diff_N, kEveryMinEffectRel * e.peak_N) << w.effect;
    report("every effect", w.effect, r, e);
  }
}

// block5_every_edge_effect with volume forces as well (data/scenarios/block5_every_feature.json):
// bit-exact on the every-feature core, and the volume forces changing the plate force by more
// than kEveryMinEffectRel of its peak.
inline void expect_every_feature(const Scenario& scenario) {
  const Model model = scenario.build_model();
  ASSERT_TRUE(model.volume.enabled);
  EXPECT_EQ(driver::edge_element_for(model), hls::kEveryFeature);
  const cosim::CosimResult r =
      expect_exact_feature_cosim(scenario, hls::kEveryFeature, scenario.default_steps(),
                                 kEveryMaxPositionErrorRel, kEveryMaxForceErrorRel);
  Model without = model;
  without.volume.enabled = false;
  const ForceEffect e = force_effect(scenario, without, r);
  EXPECT_GE(e.max_diff_N, kEveryMinEffectRel * e.peak_N);
  report("every feature", "volume", r, e);
}

}  // namespace rheo::cosim_test
