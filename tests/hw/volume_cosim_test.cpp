// Bit-exact cosimulation of the RTL cores with volume elements (VolumePreservation = 1)
// against the bit-true model: the baseline edge with volume forces at one and two lanes (the
// element schedule across lanes), a 2-D block with area forces (triangles) likewise, and
// every feature the core has at once on the shipped scenario
// data/scenarios/block5_every_feature.json, its protocol four times faster (2,500 steps, every
// phase kept; the whole protocol is whole_protocol_cosim_test.cpp under the label `long`).
// Each shows that the volume forces change the plate force by far more than the fixed-point
// error, so they could not be silently missing.
#include <gtest/gtest.h>

#include <string>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"
#include "tests/test_paths.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimResult;

// Fixed point against the double reference: the every-effect test's bounds.
constexpr double kMaxPositionErrorRel = cosim_test::kEveryMaxPositionErrorRel;
constexpr double kMaxForceErrorRel = cosim_test::kEveryMaxForceErrorRel;
constexpr double kMinEffectRel = cosim_test::kEveryMinEffectRel;

Scenario volume_block4() {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = 4;  // runs at 1, 2 and 4 lanes (ElementSchedule)
  s.block.volume.enabled = true;
  s.block.volume.kv = 2e4;
  return s;
}

// The 2-D block5 (5 x 5 particles in the x-z plane, 40 mm deep) with area preservation.
Scenario area_block5() {
  Scenario s = load_scenario("block5");
  s.block.dim = 2;
  s.block.ny = 1;
  s.block.volume.enabled = true;
  s.block.volume.kv = 800.0;  // N/m: the 3-D block's 2e4 Pa times its depth
  return s;
}

void expect_exact_at_one_and_two_lanes(const Scenario& scenario, const std::string& label) {
  const Model model = scenario.build_model();
  EXPECT_EQ(edge_element_for(model), hls::kThreeElementWithVolume);
  for (int lanes : {1, 2}) {
    cosim::CosimOptions opt;
    opt.steps = 2000;
    opt.lanes = lanes;
    opt.compare_every = 5;
    const CosimResult r = cosim::run_cosim(scenario, opt);
    EXPECT_EQ(r.element, hls::kThreeElementWithVolume.name);
    EXPECT_EQ(r.mismatches, 0) << lanes << " lanes: "
                               << (r.first.empty() ? "" : r.first.front().describe());
    EXPECT_TRUE(r.dropped_features.empty());
    EXPECT_LE(r.max_pos_err_rel, kMaxPositionErrorRel);
    EXPECT_LE(r.max_force_err_rel, kMaxForceErrorRel);
    EXPECT_EQ(r.cycles_per_step_formula,
              cycles_per_step_formula(r.edge_rows, r.particles, lanes, hls::kThreeElementWithVolume));
    EXPECT_DOUBLE_EQ(r.cycles_per_step_measured, double(r.cycles_per_step_formula)) << lanes;
    Model without = model;
    without.volume.enabled = false;
    const cosim_test::ForceEffect e = cosim_test::force_effect(scenario, without, r);
    EXPECT_GE(e.max_diff_N, kMinEffectRel * e.peak_N);
    cosim_test::report((label + (lanes == 1 ? ", 1 lane" : ", 2 lanes")).c_str(), label.c_str(), r, e);
  }
}

TEST(VolumeCosim, ABlockWithVolumeForcesIsBitExactAtOneAndTwoLanes) {
  expect_exact_at_one_and_two_lanes(volume_block4(), "volume");
}

TEST(VolumeCosim, A2DBlockWithAreaForcesIsBitExactAtOneAndTwoLanes) {
  expect_exact_at_one_and_two_lanes(area_block5(), "area");
}

TEST(EveryFeatureCosim, Block5WithEveryFeatureIsBitExactOverATimeCompressedProtocol) {
  const Scenario scenario = cosim_test::time_compressed(
      load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/block5_every_feature.json"), 4.0);
  ASSERT_EQ(scenario.default_steps(), 2500);
  cosim_test::expect_every_feature(scenario);
}

}  // namespace
}  // namespace rheo::driver
