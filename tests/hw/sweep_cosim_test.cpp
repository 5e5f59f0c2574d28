// The sweep core (rtl/rheo_sweep_core.sv with its SRAM models) against rheo_core's bit-true
// model on the same oriented model: every plate force and particle word equal, the
// measured clocks per step equal to the formula (exactly: nothing in a step depends on the
// data), under random idle input and output back-pressure; Voigt lengths read back equal;
// a load that breaks the sweep's order is flagged, not computed.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/backend/backend.hpp"
#include "host/cosim/cosim.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/device_factory.hpp"
#include "host/driver/sweep_image.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"

namespace rheo::driver {
namespace {

cosim::CosimResult expect_bit_exact(const Scenario& s, long steps, double idle, double stall,
                                    int compare_every) {
  cosim::CosimOptions opt;
  opt.steps = steps;
  opt.dut = "sweep";
  opt.compare_every = compare_every;
  opt.input_idle_prob = idle;
  opt.output_stall_prob = stall;
  opt.seed = 11;
  const cosim::CosimResult r = cosim::run_cosim(s, opt);
  EXPECT_EQ(r.mismatches, 0) << (r.first.empty() ? "" : r.first.front().describe());
  EXPECT_EQ(r.steps, steps);
  // Exactly the formula over the run commands (their steps overlap at the image's period):
  // the measured count is the core's own busy clocks over the steps.
  EXPECT_EQ(r.cycles_per_step_measured, r.cycles_per_step_expected);
  EXPECT_LT(r.max_pos_err_rel, 1e-4);
  ::testing::Test::RecordProperty("cycles_per_step", std::to_string(r.cycles_per_step_formula));
  ::testing::Test::RecordProperty("sim_cycles_per_s", std::to_string(r.sim_cycles_per_s));
  return r;
}

TEST(SweepCosim, Block5PushHoldReleaseIsBitExactUnderBackPressure) {
  const cosim::CosimResult r = expect_bit_exact(load_scenario("block5"), 3000, 0.3, 0.5, 50);
  EXPECT_EQ(r.dut_description["lanes_used"].get<int>(), 5);  // a layer each
}

TEST(SweepCosim, Block15IsBitExactAndTakesTheFormulasClocks) {
  const cosim::CosimResult r = expect_bit_exact(load_scenario("block15"), 12, 0.0, 0.0, 6);
  EXPECT_EQ(r.dut_description["lanes_used"].get<int>(), 5);
  // The paper's model in at most 70 us at 120 MHz: E / 5 lanes and the drain, within 1 %.
  EXPECT_LT(double(r.cycles_per_step_formula), 1.01 * (40727.0 / 5.0) + 64.0);
}

TEST(SweepCosim, HoldingPlateGravityAndAFixedFloorAreBitExact) {
  Scenario s = load_scenario("block5");
  s.block.nx = 6;
  s.block.ny = 4;
  s.block.nz = 9;
  s.plate_contact = PlateContact::kHoldWhilePushing;
  expect_bit_exact(s, 600, 0.1, 0.2, 20);
}

TEST(SweepCosim, VoigtLengthsReadBackEqualTheGoldenCores) {
  const Scenario s = load_scenario("block5");
  auto dut = backend::make_backend("sweep");
  auto golden = backend::make_backend("bittrue");
  const Model model = dut->prepared(s.build_model());
  dut->load(model, initial_state(model), s.options);
  golden->load(model, initial_state(model), s.options);
  std::vector<double> plate;
  for (long n = 1; n <= 400; ++n) plate.push_back(s.plate_z(model, n));
  EXPECT_EQ(dut->run(plate), golden->run(plate));
  const State a = dut->state(), b = golden->state();
  ASSERT_EQ(a.d.size(), b.d.size());
  for (std::size_t k = 0; k < a.d.size(); ++k) EXPECT_EQ(a.d[k], b.d[k]) << "edge " << k;
}

// A failing run is investigated in a waveform: the sweep core's FST and a GTKWave save file
// whose every trace is a signal of that FST (make_gtkw refuses a missing one).
TEST(SweepCosim, ATracedRunWritesAWaveformAndASaveFileForIt) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("rheo_sweep_trace_" + std::to_string(getpid()));
  fs::create_directories(dir);
  cosim::CosimOptions opt;
  opt.steps = 2;
  opt.dut = "sweep";
  opt.trace_fst = (dir / "w.fst").string();
  const cosim::CosimResult r = cosim::run_cosim(load_scenario("block5"), opt);
  EXPECT_EQ(r.mismatches, 0);
  const std::string gtkw = cosim::write_trace_gtkw(r, opt, "/usr/bin/true");
  std::ifstream in(gtkw);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("L3 TEM f_o x [N]"), std::string::npos);
  EXPECT_NE(text.find("L0 slot n (SRAM word)"), std::string::npos);
  fs::remove_all(dir);
}

// A lane whose ghost copy misses a particle with an edge into it: the core cannot sum that
// particle's force, and both the RTL and its bit-true model say so (schedule conflict)
// instead of returning words.
TEST(SweepCosim, AGhostCopyMissingACrossEdgeIsFlaggedByBothModels) {
  const Scenario s = load_scenario("block5");
  const Model m = orient_edges_low_to_high(s.build_model());
  SweepImage img = make_sweep_image(m, initial_state(m), s.options.dt);
  img.lane[1].ghost -= 1;
  for (const char* spec : {"sweep", "sweep-bittrue"}) {
    link::OpenedDevice d = link::make_sweep_device(spec);
    d.device->load_frames(sweep_frames(img), 5, true);
    try {
      d.device->run({std::int32_t(to_x_word(s.plate_z(m, 1), img.base, "plate"))});
      ADD_FAILURE() << spec << ": not flagged";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("edge schedule conflict"), std::string::npos)
          << spec << ": " << e.what();
    }
  }
}

// Steps gone ahead two clocks sooner than the host's period (host/driver/sweep_overlap.cpp):
// block5's next stream would start while the last one still runs, block15's next MPM path
// before the last step's force; the RTL's checks say so (the schedule-conflict flag, or an
// assertion where the simulation meets the clash itself) instead of returning words. At the
// period itself the tests above are bit-exact with their clocks equal to the formula.
TEST(SweepCosim, APeriodBelowTheHostsIsFlaggedNotComputed) {
  for (const char* name : {"block5", "block15"}) {
    const Scenario s = load_scenario(name);
    const Model m = orient_edges_low_to_high(s.build_model());
    SweepImage img = make_sweep_image(m, initial_state(m), s.options.dt);
    ASSERT_GT(img.period, 2) << name;
    img.period -= 2;
    link::OpenedDevice d = link::make_sweep_device("sweep");
    d.device->load_frames(sweep_frames(img), 5, true);
    std::vector<std::int32_t> plate;
    for (long n = 1; n <= 3; ++n)
      plate.push_back(std::int32_t(to_x_word(s.plate_z(m, n), img.base, "plate")));
    try {
      d.device->run(plate);
      ADD_FAILURE() << name << ": not flagged";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("edge schedule conflict") != std::string::npos ||
                  what.find("assertion failed") != std::string::npos)
          << name << ": " << what;
    }
  }
}

}  // namespace
}  // namespace rheo::driver
