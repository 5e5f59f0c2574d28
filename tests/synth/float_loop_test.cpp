// The float column of `rheo fixed` runs the reference step on its own loop: instantiated
// for double it must reproduce rheo::Simulator exactly, so the float figures measure
// float rounding and nothing else.
#include <gtest/gtest.h>

#include "host/driver/core_image.hpp"
#include "host/backend/float_simulator.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::fixedcmp {
namespace {

using backend::SieLoop;

// Steps long enough for plate contact, hold and edge clamping to matter.
constexpr int kSteps = 400;

TEST(SieLoop, InstantiatedForDoubleReproducesTheReferenceSimulatorBitForBit) {
  for (const std::string name : {"block5", "clay_push"}) {
    const Scenario scenario = load_scenario(name);
    const Model model = driver::hardware_model(scenario.build_model());
    Simulator reference(model, scenario.options);
    SieLoop<double> loop(model, scenario.options.dt);
    for (int s = 1; s <= kSteps; ++s) {
      const double plate_z =
          model.height - scenario.protocol.displacement_mm(s * scenario.options.dt) * 1e-3;
      const double f_ref = reference.step(plate_z).plate_force_N;
      ASSERT_EQ(loop.step(plate_z), f_ref) << name << " step " << s;
    }
    for (int i = 0; i < model.num_particles(); ++i) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(loop.position(i, c), reference.state().x[i][c]) << name << " particle " << i;
      }
    }
  }
}

void expect_bit_for_bit_with_volume(const Scenario& scenario) {
  const Model model =
      driver::hardware_model(scenario.build_model(), nullptr, hls::kThreeElementWithVolume);
  ASSERT_TRUE(model.volume.enabled);
  Simulator reference(model, scenario.options);
  SieLoop<double> loop(model, scenario.options.dt);
  for (int s = 1; s <= kSteps; ++s) {
    const double plate_z =
        model.height - scenario.protocol.displacement_mm(s * scenario.options.dt) * 1e-3;
    ASSERT_EQ(loop.step(plate_z), reference.step(plate_z).plate_force_N) << "step " << s;
  }
  for (int i = 0; i < model.num_particles(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(loop.position(i, c), reference.state().x[i][c]) << "particle " << i;
}

TEST(SieLoop, WithVolumeForcesReproducesTheReferenceSimulatorBitForBit) {
  Scenario scenario = load_scenario("block5");
  scenario.block.volume.enabled = true;
  scenario.block.volume.kv = 2e4;
  expect_bit_for_bit_with_volume(scenario);
}

TEST(SieLoop, With2DAreaForcesReproducesTheReferenceSimulatorBitForBit) {
  Scenario scenario = load_scenario("block5");
  scenario.block.dim = 2;
  scenario.block.ny = 1;
  scenario.block.volume.enabled = true;
  scenario.block.volume.kv = 800.0;
  expect_bit_for_bit_with_volume(scenario);
}

TEST(SieLoop, RefusesModelsWithForcesTheHardwareDoesNotCompute) {
  Model model = load_scenario("block5").build_model();
  model.topology.enabled = true;
  EXPECT_THROW(SieLoop<float>(model, 1e-4), Error);
}

}  // namespace
}  // namespace rheo::fixedcmp
