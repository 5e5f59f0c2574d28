// `rheo synth` compares like with like and says what it cannot compute: a run with the MPM
// alone has no lane fit, no core clock and no multiplier peak, and each 2003 figure stands
// only beside the model size it was measured on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli/run_rheo.hpp"

namespace {

namespace fs = std::filesystem;
using rheo::testing_support::run_rheo;

TEST(SynthCli, ASubsetOfDesignsWarnsForEveryFigureItCannotComputeAndComparesOnlyLikeSizes) {
  const fs::path out = fs::temp_directory_path() / ("rheo_synth_cli_" + std::to_string(getpid()));
  fs::remove_all(out);
  const auto r = run_rheo("synth --designs mpm --no-reference-timing -q --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out / "synth.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  fs::remove_all(out);

  EXPECT_TRUE(j["fit"]["max_lanes_xc2v6000"].is_null()) << "no lane count without tem and mpm";
  // Three figures it cannot compute, and block15, whose state does not fit the chip.
  EXPECT_EQ(j["warnings"].size(), 4u) << j["warnings"].dump(2);
  EXPECT_NE(r.output.find("warning: lanes that fit"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("block15 is NOT feasible on one XC2V6000"), std::string::npos)
      << r.output;
  EXPECT_TRUE(j["performance"]["peak_edge_updates_per_s"].is_null());
  for (const auto& row : j["performance"]["scenarios"]) {
    const std::string name = row["scenario"];
    // The paper's PC ran 5x5x5, its FPGA 15x15x16.
    EXPECT_EQ(row.contains("speedup_vs_paper_pc"), name == "block5") << name;
    EXPECT_EQ(row.contains("speedup_vs_paper_fpga"), name == "block15") << name;
    EXPECT_TRUE(row["fraction_of_multiplier_peak"].is_null()) << name;
    // A time per step is a range over the delay model's sensitivity corners, and a
    // scenario whose state needs more block RAM than the chip has is not feasible.
    const auto& range = row["estimated_us_per_step_range"];
    EXPECT_LT(range[0].get<double>(), row["estimated_us_per_step"].get<double>()) << name;
    EXPECT_GT(range[1].get<double>(), row["estimated_us_per_step"].get<double>()) << name;
    EXPECT_EQ(row["feasible_on_one_xc2v6000"].get<bool>(),
              row["ramb16_estimate"].get<int>() <= 144)
        << name;
  }
  EXPECT_EQ(j["performance"]["sensitivity"]["corners"].size(), 9u);
}

// The sweep core design (a one-lane build small enough for a test): its resources against
// the chip, block5 on it, and block15, which the build cannot hold, refused with the reason
// and not called feasible.
TEST(SynthCli, TheSweepCoreBuildIsCheckedAgainstTheChipAndRefusesAModelItCannotHold) {
  const fs::path out = fs::temp_directory_path() / ("rheo_synth_sweep_" + std::to_string(getpid()));
  fs::remove_all(out);
  const auto r = run_rheo("synth --designs sweep --sweep-build 1,128,32,512 --no-reference-timing "
                          "-q --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out / "synth.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  fs::remove_all(out);
  const auto& sweep = j["performance"]["sweep_core"];
  ASSERT_TRUE(sweep.is_object()) << j["performance"].dump(2);
  EXPECT_EQ(sweep["resources"]["mult18x18"].get<int>(), 28);  // one TEM and one MPM
  EXPECT_TRUE(sweep["fits_xc2v6000"].get<bool>());
  EXPECT_EQ(sweep["sram"]["devices"].get<int>(), 2);
  for (const auto& row : sweep["scenarios"]) {
    const std::string name = row["scenario"];
    if (name == "block5") {
      EXPECT_TRUE(row["feasible_on_one_xc2v6000"].get<bool>());
      EXPECT_EQ(row["lanes_used"].get<int>(), 1);
      // One lane: every edge in one stream, plus padding and the drain.
      EXPECT_GT(row["cycles_per_step"].get<long>(), 1036);
      const auto& range = row["estimated_us_per_step_range"];
      EXPECT_LT(range[0].get<double>(), row["estimated_us_per_step"].get<double>());
      // Steps of a command overlap: the next starts after the stream, not after the drain.
      EXPECT_GT(row["period_cycles"].get<long>(), 1036);
      EXPECT_LT(row["period_cycles"].get<long>(), row["cycles_per_step"].get<long>());
      EXPECT_LT(row["estimated_us_per_step"].get<double>(),
                row["estimated_us_one_step_alone"].get<double>());
    } else {
      EXPECT_EQ(name, "block15");
      EXPECT_FALSE(row["feasible_on_one_xc2v6000"].get<bool>());
      EXPECT_NE(row["refused_because"].get<std::string>().find("3600 particles"),
                std::string::npos);
    }
  }
  EXPECT_NE(r.output.find("block15 on the sweep core: NOT feasible"), std::string::npos) << r.output;
}

}  // namespace
