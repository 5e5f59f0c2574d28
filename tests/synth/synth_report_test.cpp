// Parsing of the Yosys reports, the Virtex-II delay model and the performance model.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>

#include "host/driver/core_image.hpp"
#include "host/synth/delay_model.hpp"
#include "host/synth/performance_model.hpp"
#include "host/synth/synth_report.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"

namespace rheo::synth {
namespace {

namespace fs = std::filesystem;

// Delay sums are exact decimal arithmetic on a few terms: rounding only.
constexpr double kDelayToleranceNs = 1e-9;

class ReportFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("rheo_synth_report_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

constexpr const char* kStatJson = R"({
  "creator": "Yosys 0.23",
  "modules": { "\\rheo_tem": { "num_cells": 20, "num_cells_by_type": {
    "FDRE": 5, "FDSE": 1, "LUT2": 3, "LUT4": 2, "SRL16E": 1, "RAM16X1D": 1,
    "MULT18X18": 4, "RAMB16_S18": 1, "MUXCY": 7, "XORCY": 7, "BUFG": 1 } } }
})";

TEST_F(ReportFiles, StatJsonCountsLutSitesFlipFlopsMultipliersAndBlockRams) {
  const Resources r = parse_stat_json(write("tem.stat.json", kStatJson), "rheo_tem");
  EXPECT_EQ(r.lut4, 3 + 2 + 1 + 2);  // LUT2 + LUT4 + SRL16E + dual-port RAM16 (2 LUTs)
  EXPECT_EQ(r.ff, 6);
  EXPECT_EQ(r.mult18, 4);
  EXPECT_EQ(r.ramb16, 1);
  EXPECT_EQ(r.carry, 7);
  EXPECT_EQ(r.cells_by_type.at("BUFG"), 1);
}

TEST_F(ReportFiles, StatJsonOfAnotherTopIsRejectedWithTheFieldName) {
  const fs::path file = write("tem.stat.json", kStatJson);
  try {
    parse_stat_json(file, "rheo_mpm");
    FAIL() << "expected rheo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("modules/\\rheo_mpm"), std::string::npos) << e.what();
  }
}

TEST_F(ReportFiles, BrokenStatJsonIsAnErrorNamingTheFile) {
  const fs::path file = write("bad.stat.json", "{ not json");
  EXPECT_THROW(parse_stat_json(file, "rheo_tem"), Error);
}

constexpr const char* kLtp = R"(
5. Executing LTP pass (find longest path).

Longest topological path in rheo_tem (length=5):
    0: \a_q [0]
    1: $w1 (via $lut_a)
    2: $w2 (via $carry_0)
    3: $w3 (via $carry_1)
    4: $w4 (via $sum)
    5: $w5 (via $mul)
)";
constexpr const char* kCells =
    "LUT4 rheo_tem/$lut_a\nMUXCY rheo_tem/$carry_0\nMUXCY rheo_tem/$carry_1\n"
    "XORCY rheo_tem/$sum\nMULT18X18 rheo_tem/$mul\n";

TEST_F(ReportFiles, LongestPathHopsAreClassifiedByCellType) {
  const LongestPath p = parse_longest_path(write("t.ltp.txt", kLtp), write("t.cells.txt", kCells));
  EXPECT_EQ(p.length, 5);
  EXPECT_EQ(p.hops_by_type.at("LUT4"), 1);
  EXPECT_EQ(p.hops_by_type.at("MUXCY"), 2);
  EXPECT_EQ(p.hops_by_type.at("XORCY"), 1);
  EXPECT_EQ(p.hops_by_type.at("MULT18X18"), 1);
}

TEST_F(ReportFiles, PathCellWithoutKnownTypeIsAnError) {
  EXPECT_THROW(
      parse_longest_path(write("t.ltp.txt", kLtp), write("t.cells.txt", "LUT4 rheo_tem/$lut_a\n")),
      Error);
}

TEST(DelayModel, PathPeriodSumsCellDelaysNetsClockToOutAndSetup) {
  LongestPath p;
  p.hops_by_type = {{"LUT4", 2}, {"MUXCY", 10}, {"XORCY", 1}};
  const Virtex2Delays d;
  const PathTiming t = estimate_timing(p, Resources{}, d);
  // Nets: one leaving the flip-flop, one after each LUT and after the XORCY.
  const double expected = d.clock_to_out.ns + 2 * d.lut.ns + 10 * d.carry_bit.ns + d.carry_sum.ns +
                          4 * d.route.ns + d.setup.ns;
  EXPECT_NEAR(t.period_ns, expected, kDelayToleranceNs);
  EXPECT_NEAR(t.fmax_mhz, 1e3 / expected, 1e-6);
  EXPECT_EQ(t.limited_by, "ltp path");
}

TEST(DelayModel, DesignWithMultipliersIsNeverFasterThanOneMultiplierStage) {
  LongestPath short_path;
  short_path.hops_by_type = {{"LUT4", 1}};
  Resources r;
  r.mult18 = 1;
  const Virtex2Delays d;
  const PathTiming t = estimate_timing(short_path, r, d);
  EXPECT_EQ(t.limited_by, "multiplier stage");
  EXPECT_GE(t.period_ns, d.multiplier.ns + d.clock_to_out.ns + d.setup.ns);
}

TEST(DelayModel, UnknownCellTypeOnThePathIsAnError) {
  LongestPath p;
  p.hops_by_type = {{"DSP48E1", 1}};
  EXPECT_THROW(estimate_timing(p, Resources{}), Error);
}

TEST(PerformanceModel, SlicesAreHalfTheLargerOfLutsAndFlipFlops) {
  Resources r;
  r.lut4 = 101;
  r.ff = 40;
  EXPECT_EQ(estimate_slices(r), 51);
  const Utilisation u = utilisation(r);
  EXPECT_NEAR(u.slices_pct, 100.0 * 51 / 33792, 1e-12);
}

TEST(PerformanceModel, LanesThatFitAreLimitedByTheScarcestResource) {
  Resources lane;
  lane.mult18 = 50;  // 144 / 50 -> 2 lanes
  lane.lut4 = 1000;
  Resources shared;
  shared.mult18 = 40;  // leaves 104 -> 2 lanes
  EXPECT_EQ(lanes_that_fit(lane, shared), 2);
  shared.mult18 = 100;  // leaves 44 -> no lane
  EXPECT_EQ(lanes_that_fit(lane, shared), 0);
}

TEST(PerformanceModel, BlockRamCountPicksTheCheapestAspectRatio) {
  EXPECT_EQ(ramb16_for_memory(512, 36), 1);
  EXPECT_EQ(ramb16_for_memory(16384, 1), 1);
  EXPECT_EQ(ramb16_for_memory(1024, 36), 2);
  EXPECT_EQ(ramb16_for_memory(4096, 96), 22);  // 2048 x 9: 2 deep x 11 wide
  EXPECT_EQ(ramb16_for_memory(100, 96), 3);    // 512 x 36 blocks side by side
}

// The core's memories at block5 capacity, one lane: per bank 6 x/p + 3 x0 words, 1/m and
// flags (one RAMB16 each at 128 x 32) and two 128 x 120 force sums (4 each); per lane the
// 2048-slot record (19 bits: 3), L and d (4 each) and material (1). Yosys 0.23 maps the
// same RTL to 28 RAMB16 + LUT RAM (docs/synthesis.md section 4).
TEST(PerformanceModel, CoreBlockRamAtBlock5CapacityCountsEveryMemoryOnce) {
  EXPECT_EQ(estimate_core_ramb16({128, 2048}, 1), 31);
  // Two lanes halve every depth (nothing is copied): per bank the same 19 blocks at 64
  // deep, per lane the 1024-slot record (17 bits: 1), L and d (2 each), material (1).
  EXPECT_EQ(estimate_core_ramb16({128, 2048}, 2), 2 * (19 + 6));
  // The same count by memory, as `rheo synth` reports it for a state that does not fit.
  const Ramb16Breakdown b = core_ramb16_breakdown({128, 2048}, 1);
  EXPECT_EQ(b.position_velocity, 6);
  EXPECT_EQ(b.home_position, 3);
  EXPECT_EQ(b.inverse_mass + b.particle_flags, 2);
  EXPECT_EQ(b.force_sums, 8);
  EXPECT_EQ(b.edge_record, 3);
  EXPECT_EQ(b.rest_length, 4);
  EXPECT_EQ(b.voigt_length, 4);
  EXPECT_EQ(b.edge_material, 1);
  EXPECT_EQ(b.total(), 31);
}

// The generated lattice has the built-in blocks' sizes (block15 is 15 x 15 x 16).
TEST(PerformanceModel, LatticeProblemHasTheBuiltInBlocksSizes) {
  for (const auto& [name, n1, n2, n3] :
       {std::tuple{"block5", 5, 5, 5}, std::tuple{"block15", 15, 15, 16}}) {
    const Model model = load_scenario(name).build_model();
    const ProblemSize lattice = lattice_problem(n1, n2, n3);
    EXPECT_EQ(lattice.particles, model.num_particles()) << name;
    EXPECT_EQ(lattice.edges, model.num_edges()) << name;
    EXPECT_EQ(static_cast<int>(lattice.ends.size()), lattice.edges);
  }
}

TEST(PerformanceModel, CycleFormulaMatchesTheDriverForEveryLaneCount) {
  const Scenario scenario = load_scenario("block5");
  const Model model = driver::hardware_model(scenario.build_model());
  const State state = initial_state(model);
  const ProblemSize size = problem_size("block5", model);
  for (int lanes = 1; lanes <= 4; ++lanes) {
    const driver::CoreImage image =
        driver::make_core_image(model, state, scenario.options.dt, lanes);
    EXPECT_EQ(edge_rows(size, lanes), image.edge_rows) << "lanes " << lanes;
    EXPECT_EQ(cycles_per_step(size, lanes),
              driver::cycles_per_step_formula(image.edge_rows, model.num_particles(), lanes))
        << "lanes " << lanes;
  }
}

}  // namespace
}  // namespace rheo::synth
