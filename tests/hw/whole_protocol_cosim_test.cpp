// The every-effect and every-feature cosimulations (every_effect_cosim_test.cpp,
// volume_cosim_test.cpp) over the whole shipped block5 protocol, 10,000 steps on the one-lane
// core: about 15 minutes of CPU together, so they carry the opt-in label `long`
// (`ctest -L long`, docs/testing.md) and the default suite runs the time-compressed protocol.
#include <gtest/gtest.h>

#include <string>

#include "sim/scenario.hpp"
#include "tests/hw/cosim_effect.hpp"
#include "tests/test_paths.hpp"

namespace rheo::driver {
namespace {

Scenario shipped(const char* name) {
  return load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/" + name);
}

TEST(WholeProtocolCosim, Block5WithEveryEdgeEffectIsBitExactOverTheWholeProtocol) {
  const Scenario scenario = shipped("block5_every_edge_effect.json");
  ASSERT_EQ(scenario.default_steps(), 10000);
  cosim_test::expect_every_edge_effect(scenario);
}

TEST(WholeProtocolCosim, Block5WithEveryFeatureIsBitExactOverTheWholeProtocol) {
  const Scenario scenario = shipped("block5_every_feature.json");
  ASSERT_EQ(scenario.default_steps(), 10000);
  cosim_test::expect_every_feature(scenario);
}

}  // namespace
}  // namespace rheo::driver
