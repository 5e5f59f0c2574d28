// Bit-exact cosimulation of the RTL core built with strain hardening (StrainHardening = 1,
// Vrheo_core_hardening_l1) against the bit-true model, plus the error of both against the
// double reference with hardening: block5 whose Voigt springs stiffen as k1 (1 + H e^2).
// Also: the core's cycles per step follow the formula with the hardening TEM's longer drain,
// a core without hardening lists it as dropped, and the host refuses an edge whose natural
// length is not its rest length (the core takes the strain from L).
#include <gtest/gtest.h>

#include <string>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimResult;

constexpr long kRunSteps = 4000;
// Fixed point against the double reference, both with hardening: the damper test's bounds
// (the hardened coefficients err by 7.6e-5 at most, hw_hardening_kernel_test).
constexpr double kMaxPositionErrorRel = 2e-5;
constexpr double kMaxForceErrorRel = 5e-4;
// Hardening must matter: the force differs from a double reference without it by far more
// than the quantisation bound.
constexpr double kMinHardeningEffectRel = 0.05;
constexpr double kHardening = 200.0;  // per strain squared

Scenario block5_with_hardening() {
  Scenario s = load_scenario("block5");
  s.block.material.hardening = kHardening;
  return s;
}

TEST(HardeningCosim, Block5WithStrainHardeningIsBitExactOnTheHardeningCore) {
  const Scenario scenario = block5_with_hardening();
  const CosimResult r = cosim_test::expect_exact_feature_cosim(
      scenario, hls::kThreeElementWithHardening, kRunSteps, kMaxPositionErrorRel,
      kMaxForceErrorRel);
  // the hardening TEM's longer drain
  EXPECT_EQ(r.cycles_per_step_formula, cycles_per_step_formula(r.edge_rows, r.particles, 1) +
                                           hls::kHardTemExtra);

  Model linear = scenario.build_model();
  for (EdgeMaterial& m : linear.materials) m.hardening = 0.0;
  const cosim_test::ForceEffect e = cosim_test::force_effect(scenario, linear, r);
  EXPECT_GE(e.max_diff_N, kMinHardeningEffectRel * e.peak_N);
  cosim_test::report("hardening", "hardening", r, e);
}

// The model picks the hardening core; a core without hardening says so: hardening is listed
// as dropped, not silently left out.
TEST(HardeningCosim, ACoreWithoutHardeningListsItAsDropped) {
  std::vector<std::string> dropped;
  hardware_model(block5_with_hardening().build_model(), &dropped, hls::kThreeElementWithDamper);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_NE(dropped[0].find("strain hardening"), std::string::npos) << dropped[0];
  EXPECT_NE(dropped[0].find("three-element+damper"), std::string::npos) << dropped[0];
  EXPECT_EQ(edge_element_for(block5_with_hardening().build_model()),
            hls::kThreeElementWithHardening);
}

// The core computes the strain from L: an edge whose L is not its rest length l0 is refused
// by name rather than hardened from the wrong length.
TEST(HardeningCosim, TheHostRefusesAnEdgeWhoseNaturalLengthIsNotItsRestLength) {
  const Scenario scenario = block5_with_hardening();
  Model model = scenario.build_model();
  model.edges[7].L *= 1.01;
  const State state = initial_state(model);
  try {
    make_core_image(model, state, scenario.options.dt, 1, FormatDesc{},
                    hls::kThreeElementWithHardening);
    FAIL() << "expected an error";
  } catch (const Error& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("edge 7"), std::string::npos) << what;
    EXPECT_NE(what.find("rest length"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rheo::driver
