// Bad input never crashes and never lies: each case a careless or hostile user tried gets a
// clear error (naming the file, field or option and what was expected), a non-zero exit, and
// leaves nothing in --out.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/cli/run_rheo.hpp"
#include "tests/cli/scratch_dir.hpp"
#include "tests/test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using rheo::testing_support::run_rheo;
using rheo::testing_support::RunResult;

class BadInputTest : public rheo::testing_support::ScratchDirTest {
 protected:
  BadInputTest() : ScratchDirTest("rheo_bad_input_") {}

  std::string out() const { return path("out"); }
  std::string scenario_text() const { return run_rheo("scenarios --show block5").output; }
  std::string scenario_with(const std::string& from, const std::string& to) const {
    std::string s = scenario_text();
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return write("scenario.json", s);
  }
  // A clear error: exit 1 (not a crash), "error:" with the expected words, no --out.
  void expect_refused(const RunResult& r, const std::vector<std::string>& words) const {
    EXPECT_EQ(r.status, 1) << r.output;  // 1: rheo's own error; a crash would be -1 or 134/139
    for (const std::string& w : words) EXPECT_NE(r.output.find(w), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out())) << r.output;
    for (const auto& e : fs::directory_iterator(root_)) {
      EXPECT_EQ(e.path().filename().string().find(".out."), std::string::npos)
          << "left behind: " << e.path();
    }
  }
  std::string data() const { return std::string(RHEO_SOURCE_DIR) + "/data/clay_fast.csv"; }

};

TEST_F(BadInputTest, DeeplyNestedScenarioIsRefusedNotACrash) {
  const std::string deep = std::string(60000, '[') + std::string(60000, ']');
  expect_refused(run_rheo("simulate --scenario " + write("deep.json", deep) + " --out " + out()),
                 {"nested deeper than"});
}

TEST_F(BadInputTest, OutNamingAnExistingFileIsRefusedByEveryCommand) {
  const std::string file = write("afile", "keep");
  std::vector<std::string> commands = {"simulate --scenario block5 --steps 2",
                                       "fixed --scenario block5 --steps 2", "synth --designs mpm",
                                       "diagnose " + data(), "fit " + data()};
#ifdef RHEO_HAVE_RTL
  commands.push_back("cosim --scenario block5 --steps 2");
#endif
  for (const std::string& cmd : commands) {
    SCOPED_TRACE(cmd);
    const RunResult r = run_rheo(cmd + " -q --out " + file);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("exists and is not a directory"), std::string::npos) << r.output;
  }
}

TEST_F(BadInputTest, MeasurementFileWithANonUtf8NameGetsItsReport) {
  const std::string name = path("clay\xff.csv");
  fs::copy_file(data(), name);
  const RunResult r = run_rheo("fit '" + name + "' --model-form column -q --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(root_ / "out" / "fit.json"));
}

TEST_F(BadInputTest, MeshesAndFilesBeyondTheSizeLimitsAreRefusedBeforeMemoryRunsOut) {
  std::string s = scenario_text();
  for (const char* axis : {"\"nx\": 5", "\"ny\": 5", "\"nz\": 5"}) {
    std::string to(axis);
    to.replace(to.size() - 1, 1, "200");
    s.replace(s.find(axis), std::string(axis).size(), to);
  }
  expect_refused(run_rheo("simulate --scenario " + write("big.json", s) + " --out " + out()),
                 {"/mesh/nx", "at most 1000000 particles"});
  expect_refused(run_rheo("simulate --scenario /dev/zero --out " + out()),
                 {"/dev/zero", "larger than"});
  // 200,001 rows: one more than a measurement file may hold.
  std::string csv = "# rheo-measurement: 1\ntime_s,plate_mm,force_N,surface_mm\n";
  for (int i = 0; i <= 200000; ++i) csv += std::to_string(i) + ",0,0,\n";
  expect_refused(run_rheo("fit " + write("long.csv", csv) + " -q --out " + out()),
                 {"long.csv", "more than 200000 data rows", "decimate"});
}

TEST_F(BadInputTest, NumericOptionsOutsideTheirRangeAreRefusedWithTheRange) {
  struct Case {
    std::string args, words;
  };
  const std::vector<Case> cases = {
      {"diagnose " + data() + " --max-dt nan", "finite time step in (0, 10]"},
      {"diagnose " + data() + " --max-dt 0", "finite time step in (0, 10]"},
      {"fit " + data() + " --max-dt -1", "finite time step in (0, 10]"},
      {"cosim --scenario block5 --steps -1", "from 1 to 1000000000"},
      {"cosim --scenario block5 --trace-steps -1", "from 0 to 1000000000"},
      {"synth --lanes 1000", "1000 not in {1,2,4}"},
      {"simulate --scenario block5 --duration 1e300", "--duration 1e+300 s: expected a duration"},
      {"simulate --scenario block5 --steps 0", "--steps: 0: expected a number of steps"},
      {"bench-link --steps -1", "from 1 to 10000000"},
      {"bench-link --state-every 0", "from 1 to 1000000"},
      {"bench-link --window 100000000", "from 1 to 65536"},
      {"simulate --scenario block5 --duration 1e-9", "--duration 1e-09 s: expected a duration"},
      {"cosim --scenario block5 --steps 2 --trace-steps 5", "--trace-steps requires --trace"},
      {"cosim --scenario block5 --steps 2 --trace ''", "--trace: expected a file name"},
      {"simulate --scenario block5 --backend bogus", "--backend: 'bogus': expected ref, float"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const RunResult r = run_rheo(c.args + " --out " + out());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(c.words), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out()));
  }
}

TEST_F(BadInputTest, JsonMistakesGetMessagesThatSayWhatIsWrong) {
  expect_refused(run_rheo("simulate --scenario " + scenario_with("\"k1\": 20000.0", "\"k1\": NaN") +
                          " --out " + out()),
                 {"scenario.json:", "NaN and Infinity are not JSON numbers"});
  expect_refused(run_rheo("simulate --scenario " +
                          scenario_with("\"nx\": 5,", "\"nx\": 5, \"nx\": 6,") + " --out " + out()),
                 {"/mesh/nx", "key given twice"});
}

TEST_F(BadInputTest, Utf8ByteOrderMarkIsReadAsText) {
  std::ifstream in(data());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const RunResult r =
      run_rheo("fit " + write("bom.csv", "\xEF\xBB\xBF" + text) + " --model-form column -q --out " +
               out());
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST_F(BadInputTest, AFewRowsGetNoConfidentDiagnosis) {
  const std::string csv =
      "# rheo-measurement: 1\ntime_s,plate_mm,force_N,surface_mm\n0,0,0,\n1,1,5,\n2,1,4,\n";
  expect_refused(run_rheo("diagnose " + write("short.csv", csv) + " -q --out " + out()),
                 {"3 samples", "at least 100"});
  expect_refused(run_rheo("fit " + write("short.csv", csv) + " -q --out " + out()),
                 {"3 samples", "parameters"});
}

TEST_F(BadInputTest, CommandsThatFailMidRunLeaveNoOutDirectory) {
  expect_refused(run_rheo("synth --designs no_such_design -q --out " + out()), {"unknown design"});
#ifdef RHEO_HAVE_RTL
  expect_refused(run_rheo("cosim --scenario " +
                          write("deep.json",
                                "[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]"
                                "]]]]]]]]]") +
                          " -q --out " + out()),
                 {"nested deeper than"});
#endif
}

TEST_F(BadInputTest, AStagingDirectoryLeftByAKilledRunIsRemovedByTheNextRun) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl(RHEO_BINARY, RHEO_BINARY, "simulate", "--scenario", "clay_push", "-q", "--out",
          out().c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the run has created its staging directory, then kill it without warning.
  bool staged = false;
  for (int i = 0; i < 200 && !staged; ++i) {
    for (const auto& e : fs::directory_iterator(root_)) {
      staged = staged || e.path().filename().string().rfind(".out.partial-", 0) == 0;
    }
    if (!staged) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  ASSERT_TRUE(staged) << "the run never staged its output";
  const RunResult r = run_rheo("simulate --scenario block5 --steps 2 -q --no-plot --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("left by an interrupted run"), std::string::npos) << r.output;
  for (const auto& e : fs::directory_iterator(root_)) {
    EXPECT_EQ(e.path().filename().string().find(".out.partial-"), std::string::npos)
        << "left behind: " << e.path();
  }
}

}  // namespace

namespace {

TEST_F(BadInputTest, AnEmptyOutIsAnOptionError) {
  const RunResult r = run_rheo("simulate --scenario block5 --steps 2 --out ''");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("rheo: error: --out: expected a directory name"), std::string::npos)
      << r.output;
}

// A file named like a built-in scenario is not silently passed over for the built-in one;
// a directory given as a scenario is named as one.
TEST_F(BadInputTest, AScenarioNameThatIsAlsoAFileOrADirectoryIsNamed) {
  const fs::path dir = fs::path(path("here"));
  fs::create_directories(dir / "block15");
  std::ofstream(dir / "block5") << "{}";
  RunResult r = run_rheo("simulate --scenario block5 --steps 2 -q --out " + out(), dir.string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("both a built-in scenario and a file"), std::string::npos) << r.output;
  r = run_rheo("simulate --scenario block15 --steps 2 -q --out " + out(), dir.string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("both a built-in scenario and a file"), std::string::npos) << r.output;
  r = run_rheo("simulate --scenario " + (dir / "block15").string() + " --steps 2 -q --out " +
               out());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("is a directory"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out()));
}

}  // namespace
