// Bit-exact cosimulation of the RTL core with every edge effect (MaxwellArms = 8,
// SeriesDamper = 1, StrainHardening = 1: Vrheo_core_every_l1) against the bit-true model,
// over the whole block5 protocol (10,000 steps), on the shipped scenario
// data/scenarios/block5_every_edge_effect.json: the force-dependent series damper, strain
// hardening and the eight-arm power-law spectrum at once. Plus the error of both against the
// double reference, and that each effect changes the plate force by far more than that
// error (so none of them could be silently missing).
#include <gtest/gtest.h>

#include <string>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimResult;

constexpr long kRunSteps = 10000;  // push, hold, release and after: the whole protocol
// Fixed point against the double reference: the damper and hardening tests' bounds.
constexpr double kMaxPositionErrorRel = 2e-5;
constexpr double kMaxForceErrorRel = 5e-4;
// Each effect must matter: without it the double model's force differs from the fixed-point
// force by far more than the quantisation bound.
constexpr double kMinEffectRel = 0.02;

Scenario every_effect_scenario() {
  return load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/block5_every_edge_effect.json");
}

TEST(EveryEffectCosim, Block5WithEveryEdgeEffectIsBitExactOverTheWholeProtocol) {
  const Scenario scenario = every_effect_scenario();
  const Model model = scenario.build_model();
  ASSERT_EQ(scenario.block.material.spectrum_arms, 8);
  ASSERT_TRUE(scenario.block.material.nonlinear);
  ASSERT_GT(scenario.block.material.hardening, 0.0);
  EXPECT_EQ(edge_element_for(model), hls::kThreeElementEveryEffect);

  const CosimResult r = cosim_test::expect_exact_feature_cosim(
      scenario, hls::kThreeElementEveryEffect, kRunSteps, kMaxPositionErrorRel,
      kMaxForceErrorRel);
  // the every-effect TEM's longer drain
  EXPECT_EQ(r.cycles_per_step_formula, cycles_per_step_formula(r.edge_rows, r.particles, 1) +
                                           hls::kHardDamperTemExtra);

  // each effect's share of the force: the double model without it
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
    const cosim_test::ForceEffect e = cosim_test::force_effect(scenario, without, r);
    EXPECT_GE(e.max_diff_N, kMinEffectRel * e.peak_N) << w.effect;
    cosim_test::report("every effect", w.effect, r, e);
  }
}

}  // namespace
}  // namespace rheo::driver
