// Bit-exact cosimulation of the RTL cores built with the force-dependent series damper
// (SeriesDamper = 1) against the bit-true model, plus the error of both against the double
// reference that has the damper: block5 whose series damper thins from c2 to c2 / 10
// between 200 Pa and 1.5 kPa of Voigt spring stress (seed 000 §3.3) on the damper core
// (Vrheo_core_damper_l1), and the same with the diagnosis's eight-arm power-law spectrum on
// the core with both (Vrheo_core_damper_arms8_l1): every material effect the core computes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/relaxation_spectrum.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"
#include "tests/hw/cosim_effect.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimResult;

// The push (2 s at 1 ms steps) and the first 2 s of the hold, where the damper's flow shows.
constexpr long kRunSteps = 4000;
// Fixed point against the double reference, both with the damper: the baseline's bounds
// (arm_cosim_test.cpp) with room for the damper's per-edge coefficients (their error is
// 1.5e-4 at most, hw_damper_kernel_test, against 2^-17 for a material's coefficient).
constexpr double kMaxPositionErrorRel = 2e-5;
constexpr double kMaxForceErrorRel = 5e-4;
// The damper must matter: the force differs from a double reference with the linear
// damper (c2 throughout) by far more than the quantisation bound.
constexpr double kMinDamperEffectRel = 0.05;

void add_damper(Scenario& s) {
  EdgeMaterial& m = s.block.material;
  m.nonlinear = true;
  m.f1 = 200.0;    // Pa
  m.f2 = 1500.0;   // Pa
  m.c2_min = m.c2 / 10.0;
}

Scenario block5_with_damper() {
  Scenario s = load_scenario("block5");
  add_damper(s);
  return s;
}

Scenario block5_with_damper_and_power_law() {
  Scenario s = block5_with_damper();
  PowerLawSpectrum p;
  p.modulus = 5.0e3;
  p.alpha = 0.3;
  p.t_lo = 0.05;
  p.t_hi = 4.0;
  set_power_law_spectrum(s.block.material, p);
  return s;
}

// Runs the cosimulation and checks it is bit-exact, keeps every material feature, tracks the
// double reference and differs from the linear damper; prints the figures under `label`.
void expect_damper_cosim(const char* label, const Scenario& scenario,
                         const hls::EdgeElement& element) {
  const CosimResult r = cosim_test::expect_exact_feature_cosim(
      scenario, element, kRunSteps, kMaxPositionErrorRel, kMaxForceErrorRel);

  // the damper's effect: against the double model with c2 throughout
  Model linear = scenario.build_model();
  for (EdgeMaterial& m : linear.materials) m.nonlinear = false;
  const cosim_test::ForceEffect e = cosim_test::force_effect(scenario, linear, r);
  EXPECT_GE(e.max_diff_N, kMinDamperEffectRel * e.peak_N);
  cosim_test::report(label, "damper", r, e);
}

TEST(DamperCosim, Block5WithTheNonlinearDamperIsBitExactOnTheDamperCore) {
  expect_damper_cosim("damper", block5_with_damper(), hls::kThreeElementWithDamper);
}

TEST(DamperCosim, Block5WithTheDamperAndThePowerLawSpectrumIsBitExactOnTheCoreWithBoth) {
  const Scenario s = block5_with_damper_and_power_law();
  ASSERT_EQ(s.block.material.spectrum_arms, 8);
  expect_damper_cosim("damper+8arms", s, hls::kThreeElementWithDamper8Arms);
}

// A core without the damper says so: the damper is listed as dropped, not silently linear.
TEST(DamperCosim, ACoreWithoutTheDamperListsItAsDropped) {
  std::vector<std::string> dropped;
  hardware_model(block5_with_damper().build_model(), &dropped, hls::kThreeElementWith8Arms);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_NE(dropped[0].find("nonlinear series damper"), std::string::npos) << dropped[0];
  EXPECT_NE(dropped[0].find("three-element+8arms"), std::string::npos) << dropped[0];
}

}  // namespace
}  // namespace rheo::driver
