// Power-up state: the one-lane core built with --x-initial unique (Vrheo_core_xinit_l1)
// starts every register and memory bit that has no reset from a random value. Under
// several seeds it must load a small model and run it word for word like the bit-true
// model, so nothing the results depend on may be left to the power-up state, and the
// testbench must not take words from the core before its reset has acted. The shipped
// variants start at zero (--x-initial fast), which would hide either.
#include <gtest/gtest.h>

#include <memory>

#include "host/driver/bittrue_transport.hpp"
#include "host/driver/device.hpp"
#include "host/driver/verilator_transport.hpp"
#include "sim/scenario.hpp"

namespace rheo::driver {
namespace {

constexpr int kSteps = 40;
// The plate starts 1 mm above the 3 x 3 x 3 block and presses into it by this fraction
// of its height over the run, so the edge forces and the plate force are non-zero.
constexpr double kPressFraction = 0.05;

class PowerUpTest : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(PowerUpTest, RandomPowerUpStateLoadsAndRunsBitExact) {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = 3;
  const Model m = s.build_model();
  const CoreImage img = make_core_image(m, initial_state(m), s.options.dt, 1);

  VerilatorOptions vo;
  vo.power_up_seed = GetParam();
  vo.seed = GetParam();
  vo.input_idle_prob = 0.2;
  vo.output_stall_prob = 0.3;
  Device rtl(std::make_unique<VerilatorTransport>(vo));
  Device bittrue(std::make_unique<BitTrueTransport>(1));
  rtl.load(img);  // throws on "bad command" or a wrong lane count in the load's status
  bittrue.load(img);

  std::vector<std::int32_t> plate(kSteps);
  for (int k = 0; k < kSteps; ++k) {
    const double z = m.height + 0.001 - (0.001 + kPressFraction * m.height) * (k + 1) / kSteps;
    plate[std::size_t(k)] = std::int32_t(to_x_word(z, img, "plate"));
  }
  const std::vector<std::int32_t> f_rtl = rtl.run(plate);
  const std::vector<std::int32_t> f_bt = bittrue.run(plate);
  EXPECT_EQ(f_rtl, f_bt);
  EXPECT_NE(f_bt.back(), 0) << "the plate should press on the block";
  EXPECT_EQ(rtl.read_particle_state(0, img.num_particles),
            bittrue.read_particle_state(0, img.num_particles));
  const int slots = img.edge_rows;  // one lane: one slot per row
  EXPECT_EQ(rtl.read_voigt_lengths(0, slots), bittrue.read_voigt_lengths(0, slots));
  const CoreStatus a = rtl.read_status(false), b = bittrue.read_status(false);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.step_count, std::uint32_t(kSteps));
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_EQ(a.lanes, 1u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, PowerUpTest, ::testing::Range(1u, 9u));

}  // namespace
}  // namespace rheo::driver
