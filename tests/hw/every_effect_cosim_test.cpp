// Bit-exact cosimulation of the RTL core with every edge effect (MaxwellArms = 8,
// SeriesDamper = 1, StrainHardening = 1: Vrheo_core_every_l1) against the bit-true model on
// the shipped scenario data/scenarios/block5_every_edge_effect.json: the force-dependent
// series damper, strain hardening and the eight-arm power-law spectrum at once. Plus the error
// of both against the double reference, and that each effect changes the plate force by far
// more than that error (so none of them could be silently missing). The protocol runs four
// times faster here (2,500 steps, every phase kept); the whole 10,000-step protocol is
// whole_protocol_cosim_test.cpp under the label `long`.
#include <gtest/gtest.h>

#include <string>

#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"
#include "tests/test_paths.hpp"

namespace rheo::driver {
namespace {

TEST(EveryEffectCosim, Block5WithEveryEdgeEffectIsBitExactOverATimeCompressedProtocol) {
  const Scenario scenario = cosim_test::time_compressed(
      load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/block5_every_edge_effect.json"),
      4.0);
  ASSERT_EQ(scenario.default_steps(), 2500);
  cosim_test::expect_every_edge_effect(scenario);
}

}  // namespace
}  // namespace rheo::driver
