// End to end: the fixed-vs-double comparison on block5 produces every field fixed.json
// promises, and the hardware format meets the accuracy bound of issue 5; a word length is
// judged on its plate force as well as its positions (issue 40).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/fixedcmp/compare.hpp"
#include "sim/scenario.hpp"
#include "tests/cli/run_rheo.hpp"

namespace rheo::fixedcmp {
namespace {

namespace fs = std::filesystem;

// Issue 5: max position error at most 1e-3 of the object size.
constexpr double kPositionBoundRel = 1e-3;
// Moderate length for CI; the full 1e5-step figure is in docs/synthesis.md.
constexpr long long kSteps = 10000;

TEST(FixedComparison, HardwareFormatMeetsTheBoundOnBlock5AndReportsAllFields) {
  CompareOptions options;
  options.steps = kSteps;
  const std::vector<std::string> specs = {"float", "fixed:q27_nearest_op18",
                                          "fixed:q27_truncate_op18", "fixed:q21_nearest"};
  nlohmann::json result = compare(load_scenario("block5"), specs, options);
  judge(result, Bounds{});
  for (const char* key : {"scenario", "steps", "object_size_m", "backends",
                          "peak_reference_plate_force_N", "dropped_features"}) {
    EXPECT_TRUE(result.contains(key)) << key;
  }
  ASSERT_EQ(result["backends"].size(), specs.size());
  for (const auto& b : result["backends"]) {
    for (const char* key : {"name", "kind", "steps_reached", "completed", "refused",
                            "max_position_error_rel", "plate_force_error_max_N",
                            "plate_force_error_max_rel", "plate_force_error_rms_N", "checkpoints",
                            "meets_bounds", "bound_failures"}) {
      EXPECT_TRUE(b.contains(key)) << b["name"] << " lacks " << key;
    }
    EXPECT_EQ(b["steps_reached"], kSteps) << b["name"];
    // Checkpoints at 1e3 and 1e4 steps (the run's end).
    ASSERT_EQ(b["checkpoints"].size(), 2u) << b["name"];
    EXPECT_EQ(b["checkpoints"][0]["step"], 1000);
    EXPECT_EQ(b["checkpoints"][1]["step"], kSteps);
  }
  const auto& hardware = result["backends"][1];
  EXPECT_EQ(hardware["hardware_format"], true);
  EXPECT_LE(hardware["max_position_error_rel"].get<double>(), kPositionBoundRel);
  EXPECT_GT(hardware["max_position_error_rel"].get<double>(), 0.0)
      << "a bit-true model identical to double would mean the comparison is not running";
  EXPECT_TRUE(hardware["meets_bounds"].get<bool>()) << hardware["bound_failures"];
  EXPECT_EQ(result["force_bound_rel"], Bounds{}.force_rel);
  // q21 keeps its positions within the bound (1.2e-4 of the size) but its plate force is
  // off by 1.4 % of the peak in one step during the release (measured: step 6,019): it
  // fails on the force alone. Judged on positions only, it passed.
  const auto& q21 = result["backends"][3];
  EXPECT_LE(q21["max_position_error_rel"].get<double>(), kPositionBoundRel);
  EXPECT_GT(q21["plate_force_error_max_rel"].get<double>(), Bounds{}.force_rel);
  EXPECT_FALSE(q21["meets_bounds"].get<bool>());
  ASSERT_EQ(q21["bound_failures"].size(), 1u) << q21["bound_failures"];
  EXPECT_NE(q21["bound_failures"][0].get<std::string>().find("plate force error"),
            std::string::npos);
}

// `rheo fixed` on block5 at mass scale 3e7 (the reference pushes back with 10.8 N): the
// 19- and 27-bit formats returned 0 N for most of the push while their positions stayed
// within 1e-5 of the size, and fixed.json called both word lengths passing. Now they refuse
// the model before the run (their gravity word rounds to 0, their plate rule cannot resolve
// the force) and fail the bounds; the 35-bit format computes it (force error 6e-6 of the
// peak) and passes.
// A run in which the plate never pushes has no force to judge a format by: refused (every
// format "met" the bound by an error of 0 of a 0 N peak).
TEST(FixedComparison, ARunWithoutPlateForceIsRefusedNotPassed) {
  const fs::path dir =
      fs::temp_directory_path() / ("rheo_fixed_noload_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const testing_support::RunResult r = testing_support::run_rheo(
      "fixed --scenario block5 --steps 1 --no-sweep -q --out " + (dir / "out").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("the plate force is 0 N in all 1 steps"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(FixedComparison, AWordLengthWhosePlateForceIsWrongDoesNotPass) {
  const fs::path dir =
      fs::temp_directory_path() / ("rheo_fixed_e2e_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  nlohmann::json scenario = nlohmann::json::parse(
      testing_support::run_rheo("scenarios --show block5").output);
  scenario["name"] = "block5_mass_scale_3e7";
  scenario["integrator"]["mass_scale"] = 3e7;
  const fs::path file = dir / "scenario.json";
  std::ofstream(file) << scenario.dump(2);
  const testing_support::RunResult r = testing_support::run_rheo(
      "fixed --scenario " + file.string() + " --steps 1500 --no-sweep -q --out " +
      (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(dir / "out" / "fixed.json");
  const nlohmann::json result = nlohmann::json::parse(in);
  const nlohmann::json& meets = result["frac_x_meets_bound"];
  auto passes = [&](int frac_x) {
    for (const auto& entry : meets) {
      if (entry[0] == frac_x) return entry[1].get<bool>();
    }
    ADD_FAILURE() << "no entry for frac_x " << frac_x << " in " << meets;
    return true;
  };
  EXPECT_FALSE(passes(19)) << r.output;
  EXPECT_FALSE(passes(27)) << r.output;
  EXPECT_TRUE(passes(35)) << r.output;
  for (const auto& b : result["backends"]) {
    // Whatever passes keeps its plate force within the bound.
    if (b.value("meets_bounds", true)) {
      EXPECT_LE(b["plate_force_error_max_rel"].get<double>(), result["force_bound_rel"].get<double>())
          << b["name"];
    }
  }
  EXPECT_NE(r.output.find("refused before the run: mass_scale = 3e+07"), std::string::npos)
      << r.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rheo::fixedcmp
