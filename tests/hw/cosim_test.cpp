// Bit-exact cosimulation of the RTL core against the bit-true model on the block5
// scenario (pushed, held, released), for 1 and 2 lanes and both plate rules, with the fixed-vs-double error
// and the cycle count checked.
//
// The default suite (label cosim) runs block5's protocol four times faster: every knot and the
// run length divided by 4 (cosim_test::time_compressed), 2,500 steps that keep the push, the
// hold, the release and the rest. Built with RHEO_COSIM_WHOLE_PROTOCOL
// (hw_cosim_whole_protocol_test, label long), the same tests run the whole 10,000 steps.
#include <gtest/gtest.h>

#include <algorithm>

#include "host/cosim/cosim.hpp"
#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"

#ifdef RHEO_COSIM_WHOLE_PROTOCOL
#define RHEO_COSIM_SUITE CosimWholeProtocol
#else
#define RHEO_COSIM_SUITE Cosim
#endif

namespace rheo::driver {
namespace {

using cosim::CosimOptions;
using cosim::CosimResult;
using cosim::run_cosim;

// 10,000 steps of block5 cover its push, hold and release (10 s at dt = 1 ms with the
// built-in scenario at the time of writing); the default suite runs them time-compressed.
#ifdef RHEO_COSIM_WHOLE_PROTOCOL
constexpr long kCompression = 1;
#else
constexpr long kCompression = 4;
#endif
constexpr long kLongRunSteps = 10000 / kCompression;
// Measured cycles per step may differ from the formula by at most 2 % (issue 3).
constexpr double kCycleFormulaTolerance = 0.02;
// Fixed point against double after the whole run: positions within 1e-3 of the object size
// (the hardware target, docs/hardware.md "Verification"; quantisation of x (2^-27 units)
// and p (2^-31 units) per step).
constexpr double kMaxPositionErrorRel = 1e-3;
// The plate-force word is compared every step; the 750 particle state words every 5th
// step, which keeps the read-back clocks (3 per word) from dominating the test time; the
// whole state after the last step.
// `rheo cosim` chooses K automatically by default (below).
constexpr int kCompareStateEvery = 5;

CosimResult expect_bit_exact(int lanes, long steps,
                             PlateContact contact = PlateContact::kPenetration) {
  CosimOptions opt;
  opt.steps = steps;
  opt.lanes = lanes;
  opt.compare_every = kCompareStateEvery;
  Scenario scenario =
      cosim_test::time_compressed(load_scenario("block5"), static_cast<double>(kCompression));
  scenario.plate_contact = contact;
  const CosimResult r = run_cosim(scenario, opt);
  EXPECT_TRUE(r.dropped_features.empty()) << r.dropped_features.front();
  EXPECT_EQ(r.mismatches, 0) << (r.first.empty() ? "" : r.first.front().describe());
  EXPECT_EQ(r.steps, steps);
  // After the last step the whole state, the edges' Voigt lengths too.
  EXPECT_GE(r.final_state_words, 6L * r.particles + r.edges);
  EXPECT_LE(r.max_pos_err_rel, kMaxPositionErrorRel);
  EXPECT_NEAR(r.cycles_per_step_measured, double(r.cycles_per_step_formula),
              kCycleFormulaTolerance * r.cycles_per_step_formula);
  ::testing::Test::RecordProperty("max_pos_err_rel", std::to_string(r.max_pos_err_rel));
  ::testing::Test::RecordProperty("sim_cycles_per_s", std::to_string(r.sim_cycles_per_s));
  return r;
}

// Steps where the plate force reads <= 0 N between the first contact and the start of the
// release (block5: the push ends at 2 s, the hold at 5 s, dt = 1 ms; both divided by the
// compression).
int zero_force_steps_before_release(const std::vector<double>& force) {
  constexpr std::size_t kReleaseStep = 5000 / kCompression;
  int zeros = 0;
  bool touched = false;
  for (std::size_t s = 0; s < std::min(force.size(), kReleaseStep); ++s) {
    touched = touched || force[s] > 0.0;
    zeros += touched && force[s] <= 0.0;
  }
  return zeros;
}

// The penetration rule drops the plate force to 0 N at the end of the push (the artefact
// PlateContact::kHoldWhilePushing removes), in the core as in the reference.
TEST(RHEO_COSIM_SUITE, Block5PushHoldReleaseIsBitExactWithOneLane) {
  const CosimResult r = expect_bit_exact(1, kLongRunSteps);
  EXPECT_GT(zero_force_steps_before_release(r.force_ref_N), 0);
  EXPECT_EQ(zero_force_steps_before_release(r.force_fixed_N),
            zero_force_steps_before_release(r.force_ref_N));
}

TEST(RHEO_COSIM_SUITE, Block5PushHoldReleaseIsBitExactWithTwoLanes) { expect_bit_exact(2, kLongRunSteps); }

// The plate rule of the fits (PlateContact::kHoldWhilePushing): the core keeps a particle
// it held while the particle pushes, from the previous plate height it keeps.
TEST(RHEO_COSIM_SUITE, Block5WithHoldWhilePushingIsBitExactWithTwoLanes) {
  const CosimResult r = expect_bit_exact(2, kLongRunSteps, PlateContact::kHoldWhilePushing);
  // Measured 2026-11-23: 1.6e-5 of the peak force (the penetration rule: 5.3e-5).
  EXPECT_LE(r.max_force_err_rel, 1e-3);
  EXPECT_EQ(zero_force_steps_before_release(r.force_fixed_N), 0);
  EXPECT_EQ(zero_force_steps_before_release(r.force_ref_N), 0);
}

#ifndef RHEO_COSIM_WHOLE_PROTOCOL
// The automatic interval (CosimOptions::compare_every = 0, `rheo cosim`'s default): after
// step 1 it measures one read-back and one step in simulated cycles and compares every
// ceil(read-back / step) steps, and always after the last step.
TEST(Cosim, TheAutomaticCompareIntervalFollowsTheReadBackCost) {
  CosimOptions opt;
  opt.steps = 23;
  opt.lanes = 2;
  opt.compare_every = 0;
  opt.run_reference = false;
  std::vector<long> compared;
  opt.progress = [&compared](long step) { compared.push_back(step); };
  const CosimResult r = run_cosim(load_scenario("block5"), opt);
  EXPECT_EQ(r.mismatches, 0);
  ASSERT_GT(r.step_cycles, 0u);
  ASSERT_GT(r.readback_cycles, r.step_cycles) << "block5's read-back outweighs a step";
  const long k = long((r.readback_cycles + r.step_cycles - 1) / r.step_cycles);
  EXPECT_EQ(r.compare_every, k);
  ASSERT_GE(compared.size(), 2u);
  EXPECT_EQ(compared.front(), 1);
  for (std::size_t i = 1; i + 1 < compared.size(); ++i)
    EXPECT_EQ(compared[i] - compared[i - 1], k) << "comparison " << i;
  EXPECT_EQ(compared.back(), 23);
  RecordProperty("compare_every", std::to_string(r.compare_every));
}
#endif

}  // namespace
}  // namespace rheo::driver
