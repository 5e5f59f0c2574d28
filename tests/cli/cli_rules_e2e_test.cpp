// One rule for every command: an existing non-empty --out is refused (and left untouched)
// unless --force; --lanes takes one set of values with one default; `rheo --version`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hls/fixed_format.hpp"
#include "tests/cli/run_rheo.hpp"
#include "tests/test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using rheo::testing_support::run_rheo;

class CliRulesTest : public testing::Test {
 protected:
  void SetUp() override {
    // Built with append(): operator+ chains trip GCC 12's -Wrestrict.
    std::string name("rheo_cli_rules_");
    name.append(testing::UnitTest::GetInstance()->current_test_info()->name());
    root_ = fs::temp_directory_path() / name;
    fs::remove_all(root_);
    fs::create_directories(root_ / "out");
    std::ofstream(root_ / "out" / "keep.txt") << "user data\n";
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string out() const { return (root_ / "out").string(); }
  fs::path root_;
};

// `rheo cosim` needs the Verilator core. A build without it (RHEO_WITH_RTL=OFF, such as the
// sanitizer build of scripts/test) only says so: RHEO_HAVE_RTL leaves cosim out of the cases.

// Every command that writes a results directory, with arguments that would make it run.
std::vector<std::string> commands_with_out() {
  // The column model (the fast first guess): these tests are about the command line rules.
  const std::string data =
      std::string(RHEO_SOURCE_DIR) + "/data/clay_fast.csv --model-form column";
  std::vector<std::string> commands = {"simulate --scenario block5 --steps 5 --quiet",
                                       "fit " + data + " --quiet", "diagnose " + data + " --quiet",
                                       "fixed --scenario block5 --steps 5 --no-sweep --quiet",
                                       "synth --designs mpm --no-reference-timing --quiet"};
#ifdef RHEO_HAVE_RTL
  commands.push_back("cosim --scenario block5 --steps 5 --quiet");
#endif
  return commands;
}

TEST_F(CliRulesTest, EveryCommandRefusesANonEmptyOutDirectoryAndLeavesItAsItWas) {
  for (const std::string& cmd : commands_with_out()) {
    SCOPED_TRACE(cmd);
    const auto r = run_rheo(cmd + " --out " + out());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("not empty"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
    // Nothing added, nothing removed, no staging directory left beside it.
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(root_ / "out")) {
      names.push_back(e.path().filename().string());
    }
    EXPECT_EQ(names, std::vector<std::string>{"keep.txt"});
    for (const auto& e : fs::directory_iterator(root_)) {
      EXPECT_EQ(e.path().filename().string().find(".out."), std::string::npos)
          << "left behind: " << e.path();
    }
  }
}

TEST_F(CliRulesTest, ForceReplacesTheOldContentOnlyAfterTheRunSucceeded) {
  // A cheap command of each kind that runs fully here: simulate and fixed.
  for (const std::string& cmd : {std::string("simulate --scenario block5 --steps 5 --quiet "
                                             "--no-plot"),
                                 std::string("fixed --scenario block5 --steps 5 --no-sweep -q")}) {
    SCOPED_TRACE(cmd);
    const auto r = run_rheo(cmd + " --force --out " + out());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(fs::exists(root_ / "out" / "keep.txt"));
    std::ofstream(root_ / "out" / "keep.txt") << "user data\n";
  }
}

TEST_F(CliRulesTest, EveryCommandWithLanesTakesTheSameCountsAndDefault) {
  const std::vector<std::string> commands = {"simulate", "cosim", "fixed", "synth", "cosim-server"};
  for (const std::string& cmd : commands) {
    SCOPED_TRACE(cmd);
    const auto help = run_rheo(cmd + " --help");
    ASSERT_EQ(help.status, 0) << help.output;
    // CLI11 prints the accepted set and the default beside the option: "INT:{1,2,4}=1".
    EXPECT_NE(help.output.find("--lanes"), std::string::npos) << help.output;
    std::string default_text("{1,2,4}=");
    default_text.append(std::to_string(rheo::hls::kDefaultLanes));
    EXPECT_NE(help.output.find(default_text), std::string::npos) << help.output;
  }
}

TEST_F(CliRulesTest, LaneCountOutsideTheSetIsRefusedBeforeAnythingRuns) {
  const auto r = run_rheo("simulate --scenario block5 --steps 5 --quiet --lanes 3 --out " +
                          (root_ / "new").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--lanes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(root_ / "new"));
}

// block5 with a short push-hold-release: 0.4 mm at 4 mm/s, 0.05 s hold, 0.05 s after:
// 0.3 s, 300 steps of 1 ms.
std::string write_short_scenario(const fs::path& dir) {
  const auto show = run_rheo("scenarios --show block5");
  nlohmann::json j = nlohmann::json::parse(show.output);
  j["name"] = "block5_short";
  j["protocol"] = {{"type", "push_hold_release"},
                   {"depth_mm", 0.4},
                   {"speed_mm_s", 4},
                   {"hold_s", 0.05},
                   {"after_s", 0.05}};
  const std::string path = (dir / "short.json").string();
  std::ofstream(path) << j.dump(2);
  return path;
}

// Progress of a long run, one command per test (each is a minute under the sanitizers).
TEST_F(CliRulesTest, LongRunsShowProgressWithAnEtaAndDefaultStepsCoverTheProtocol) {
  const std::string scenario = write_short_scenario(root_);
  constexpr long long kProtocolSteps = 300;
  struct Case {
    std::string command, json_file;
  };
  std::vector<Case> cases = {{"fixed --no-sweep", "fixed.json"}};
#ifdef RHEO_HAVE_RTL
  cases.push_back({"cosim", "cosim.json"});
#endif
  for (const Case& c : cases) {
    SCOPED_TRACE(c.command);
    const fs::path dir = root_ / "run";
    // Progress goes to stderr; not a terminal here, so it prints a line about every 10 %.
    const auto r = run_rheo(c.command + " --scenario " + scenario + " --out " + dir.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("ETA"), std::string::npos) << r.output;
    std::ifstream in(dir / c.json_file);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["steps"].get<long long>(), kProtocolSteps);
    fs::remove_all(dir);
  }
  // --quiet silences it.
  const auto quiet =
      run_rheo("fixed --no-sweep -q --scenario " + scenario + " --out " + (root_ / "q").string());
  ASSERT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("ETA"), std::string::npos) << quiet.output;
}

// The first 30 s of the shipped clay_fast.csv (the push and the start of the hold): the
// same header and columns, a quarter of the record, and a column fit's work is in proportion
// to the record's length (the sanitizer build runs a column diagnosis 15 times slower than
// the main build). What these tests check is the progress display.
std::string write_short_clay(const fs::path& dir) {
  std::ifstream in(std::string(RHEO_SOURCE_DIR) + "/data/clay_fast.csv");
  const fs::path out_path = dir / "clay_fast_30s.csv";
  std::ofstream out(out_path);
  std::string line;
  bool header_seen = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || !header_seen) {
      header_seen = header_seen || (!line.empty() && line[0] != '#');
      out << line << '\n';
    } else if (std::stod(line.substr(0, line.find(','))) <= 30.0) {
      out << line << '\n';
    }
  }
  return out_path.string() + " --model-form column";
}

TEST_F(CliRulesTest, ADiagnosisShowsItsModelFitsWithAnEta) {
  const std::string data = write_short_clay(root_);
  const auto diagnose = run_rheo("diagnose " + data + " --out " + (root_ / "d").string());
  ASSERT_EQ(diagnose.status, 0) << diagnose.output;
  EXPECT_NE(diagnose.output.find("model fits"), std::string::npos) << diagnose.output;
  EXPECT_NE(diagnose.output.find("ETA"), std::string::npos) << diagnose.output;
}

TEST_F(CliRulesTest, AFitShowsItsSolverIterations) {
  const std::string data = write_short_clay(root_);
  const auto fit = run_rheo("fit " + data + " --out " + (root_ / "f").string());
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("iteration"), std::string::npos) << fit.output;
}

TEST_F(CliRulesTest, VersionNamesTheProjectVersionAndCommit) {
  const auto r = run_rheo("--version");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("rheo ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("commit"), std::string::npos) << r.output;
}

}  // namespace
