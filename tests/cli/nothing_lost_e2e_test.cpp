// Nothing lost, nothing silent: what a hostile user tried against the commands that write
// results. --force never deletes an input; every output path (the waveform too) follows one
// staging and overwrite rule; a signal leaves nothing half-written and ends with 128 + its
// number; option errors exit 2 with rheo's prefix and the range in words; a run that would
// fill the disk is refused before it starts; a record given twice, a held-out record that is
// a fit record and degenerate fields are refused by name; a poor fit says so; the object
// model failing is an error unless the column's first guess is asked for.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
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

class NothingLost : public rheo::testing_support::ScratchDirTest {
 protected:
  NothingLost() : ScratchDirTest("rheo_nothing_lost_") {}
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static std::string data() { return std::string(RHEO_SOURCE_DIR) + "/data/clay_fast.csv"; }
  // Nothing staged is left next to `dir`'s entries.
  void expect_no_staging() const {
    for (const auto& e : fs::recursive_directory_iterator(root_)) {
      const std::string n = e.path().filename().string();
      EXPECT_TRUE(n.find(".partial-") == std::string::npos && n.find(".old-") == std::string::npos)
          << "left behind: " << e.path();
    }
  }
  // Runs rheo in `dir` as its working directory.
  static RunResult run_in(const std::string& dir, const std::string& args) {
    return run_rheo(args, dir);
  }
  // Starts rheo, waits until it has staged its output in root_, sends `sig`, and returns
  // the exit status (or -1 when it died by the signal, as before this rule).
  int interrupted_exit(const std::vector<std::string>& args, int sig) const {
    const pid_t child = fork();
    if (child == 0) {
      std::vector<char*> argv{const_cast<char*>(RHEO_BINARY)};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(RHEO_BINARY, argv.data());
      _exit(127);
    }
    bool staged = false;
    for (int i = 0; i < 3000 && !staged; ++i) {
      for (const auto& e : fs::directory_iterator(root_)) {
        staged = staged || e.path().filename().string().find(".partial-") != std::string::npos;
      }
      if (!staged) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(staged) << "the run never staged its output";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // into the run's work
    kill(child, sig);
    int status = 0;
    waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

};

TEST_F(NothingLost, ForceNeverDeletesAFileTheCommandReads) {
  const std::string csv = read(data());
  const std::string in_out = write("d/data.csv", csv);
  RunResult r = run_rheo("fit " + in_out + " --model-form column -q --out " + path("d") + " --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("which this command reads"), std::string::npos) << r.output;
  EXPECT_EQ(read(in_out), csv) << "the input was deleted or changed";

  // Through a symbolic link outside --out that points into it.
  fs::create_symlink(in_out, root_ / "alias.csv");
  r = run_rheo("fit " + path("alias.csv") + " --model-form column -q --out " + path("d") +
               " --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(read(in_out), csv);

  const std::string scenario = write("s/my.json", run_rheo("scenarios --show block5").output);
  const std::string scenario_text = read(scenario);
  r = run_rheo("simulate --scenario " + scenario + " --steps 2 --no-plot -q --out " + path("s") +
               " --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(read(scenario), scenario_text);

  // --out . --force in a folder with the user's files: the working directory is never
  // replaced.
  const std::string keep = write("w/notes.txt", "mine");
  r = run_in(path("w"), "simulate --scenario block5 --steps 2 --no-plot -q --out . --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("working directory"), std::string::npos) << r.output;
  EXPECT_EQ(read(keep), "mine");
  expect_no_staging();

  // Still allowed: replacing an old result that holds no input.
  write("old/force.csv", "old result");
  r = run_rheo("simulate --scenario block5 --steps 2 --no-plot -q --out " + path("old") + " --force");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(read(path("old/force.csv")), "old result");
}

// What a hostile retrial found after the rule above: a file or folder with a staging-like
// name, a ".." after a symbolic link, and special files as --trace targets.
TEST_F(NothingLost, StagingNamesLinksAndSpecialFilesNeverCostAnInput) {
  const std::string block5 = run_rheo("scenarios --show block5").output;
  // An input whose name looks like a leftover staging directory of --out, and a folder of
  // the user's with such a name: neither is a leftover of a run (no marker), neither goes.
  const std::string odd = write("l1/.o1.partial-999999-ABCDEF", block5);
  const std::string mine = write("l1/.o1.partial-999998-ABCDEF/notes.txt", "mine");
  RunResult r = run_in(path("l1"), "simulate --scenario ./.o1.partial-999999-ABCDEF --steps 2 "
                                   "--no-plot -q --out o1");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read(odd), block5) << "the scenario was deleted";
  EXPECT_EQ(read(mine), "mine") << "the user's folder was deleted";

  // ".." after a symbolic link: the kernel goes up from the link's target. L/../s.json is
  // real/s.json, an input inside --out real.
  const std::string in_real = write("real/s.json", block5);
  fs::create_directories(path("real/sub"));
  fs::create_directory_symlink(path("real/sub"), path("L"));
  r = run_rheo("simulate --scenario " + path("L") + "/../s.json --steps 2 --no-plot -q --out " +
               path("real") + " --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("which this command reads"), std::string::npos) << r.output;
  EXPECT_EQ(read(in_real), block5);

  // --out other/M/.. with M a link to elsewhere/z is elsewhere, as the kernel says: the
  // results go there, and other's content stays.
  const std::string precious = write("other/precious.txt", "keep");
  write("elsewhere/z/old.txt", "old");
  fs::create_directory_symlink(path("elsewhere/z"), path("other/M"));
  r = run_rheo("simulate --scenario block5 --steps 2 --no-plot -q --out " + path("other/M") +
               "/.. --force");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read(precious), "keep");
  EXPECT_TRUE(fs::exists(path("elsewhere/force.csv"))) << r.output;

  // An --out that is a link to nothing is refused before the run, not after it.
  fs::create_directory_symlink(path("nowhere"), path("dangling"));
  r = run_rheo("simulate --scenario block5 --steps 2 --no-plot -q --out " + path("dangling"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("which does not exist"), std::string::npos) << r.output;

#ifdef RHEO_HAVE_RTL
  // --force replaces an earlier waveform, never a pipe (or a device, or a socket).
  ASSERT_EQ(mkfifo(path("pipe").c_str(), 0600), 0);
  r = run_rheo("cosim --scenario block5 --steps 2 -q --trace " + path("pipe") + " --force --out " +
               path("c"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_fifo(path("pipe")));
#endif
}

#ifdef RHEO_HAVE_RTL
TEST_F(NothingLost, AWaveformFollowsTheRuleOfTheOutputDirectory) {
  // An existing file outside --out is not overwritten without --force...
  const std::string wave = write("w.fst", "someone's waveform");
  RunResult r = run_rheo("cosim --scenario block5 --steps 2 -q --trace " + wave + " --out " +
                         path("c"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("exists"), std::string::npos) << r.output;
  EXPECT_EQ(read(wave), "someone's waveform");
  EXPECT_FALSE(fs::exists(path("c")));
  // ... nor, with --force, when it is an input.
  const std::string scenario = write("b5.json", run_rheo("scenarios --show block5").output);
  const std::string scenario_text = read(scenario);
  r = run_rheo("cosim --scenario " + scenario + " --steps 2 -q --trace " + scenario + " --out " +
               path("c") + " --force");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(read(scenario), scenario_text);
  // A new one outside --out appears with its save file only when the run succeeded.
  r = run_rheo("cosim --scenario block5 --steps 2 -q --trace " + path("t/new.fst") + " --out " +
               path("c"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("t/new.fst")));
  EXPECT_TRUE(fs::exists(path("t/new.gtkw")));
  expect_no_staging();
}

// A waveform is an output like any other: one that would exceed --max-output-gb is refused
// before the core is loaded, with the estimate and what makes it up, and nothing is written.
TEST_F(NothingLost, AWaveformOverTheOutputBudgetIsRefusedBeforeTheRun) {
  // block5's whole protocol traced: 10,000 steps x 1,218 clocks, about 12 GB.
  RunResult r = run_rheo("cosim --scenario block5 -q --trace-steps 0 --trace " +
                         path("w/all.fst") + " --out " + path("c"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("rheo: error: this run would write about 12.2 GB, more than the 2 GB "
                          "allowed (waveform of 10000 steps x 1218 clocks per step"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--trace-steps traces fewer"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--max-output-gb"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("w/all.fst")));
  EXPECT_FALSE(fs::exists(path("c")));
  // Two traced steps (about 2.4 MB) against a 1 MB limit, then within the default one.
  r = run_rheo("cosim --scenario block5 --steps 2 -q --max-output-gb 0.001 --trace " +
               path("w/a.fst") + " --out " + path("c"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("waveform of 2 steps"), std::string::npos) << r.output;
  r = run_rheo("cosim --scenario block5 --steps 2 -q --trace " + path("w/a.fst") + " --out " +
               path("c"));
  EXPECT_EQ(r.status, 0) << r.output;
  expect_no_staging();
}
#endif

TEST_F(NothingLost, ASignalLeavesNothingAndEndsWith128PlusItsNumber) {
  struct Case {
    std::vector<std::string> args;
    int sig;
  };
  const std::string out = path("out");
  const std::vector<Case> cases = {
      // clay_push's 86 s take the fast path about 0.2 s, as long as the wait before the
      // signal: 2e7 steps (5.5 h simulated) keep the run busy when the signal comes.
      {{"simulate", "--scenario", "clay_push", "--steps", "20000000", "-q", "--out", out}, SIGINT},
      {{"simulate", "--scenario", "clay_push", "--steps", "20000000", "-q", "--out", out}, SIGHUP},
      {{"fit", data(), "--model", "second_relaxation_time", "-q", "--out", out}, SIGTERM},
      {{"diagnose", data(), "-q", "--out", out}, SIGINT},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args.front() + " " + std::to_string(c.sig));
    EXPECT_EQ(interrupted_exit(c.args, c.sig), 128 + c.sig);
    EXPECT_FALSE(fs::exists(out));
    expect_no_staging();
  }
}

TEST_F(NothingLost, OptionErrorsExitTwoWithThePrefixAndTheRangeInWords) {
  struct Case {
    std::string args, words;
  };
  const std::vector<Case> cases = {
      {"simulate --scenario block5 --duration -1", "a number greater than 0"},
      {"simulate --scenario block5 --duration 0x10", "a number greater than 0"},
      {"cosim --scenario block5 --idle-prob 2", "a number from 0 to 0.95"},
      {"cosim --scenario block5 --compare-every -1", "from 0 to 1000000000"},
      {"simulate --scenario block5 --max-output-gb -1", "a size in GB"},
      {"simulate --scenario block5 --no-such-option", "--no-such-option"},
      // The fit and diagnosis options are checked when the options are read, before any
      // input file is (they exited 1 after reading the data).
      {"fit " + data() + " --model bogus", "expected three_element or one of"},
      {"fit " + data() + " --mesh 2d:0x0", "2 to 12 particles per axis"},
      {"diagnose " + data() + " --mesh 3d:auto", "expected 2d:auto"},
      {"fit " + data() + " --strain 0", "a step strain between 0 and 1"},
      {"diagnose " + data() + " --geometry 10x10", "expected HxWxD in mm"},
      {"fit " + data() + " --as table", "relaxation_table"},
      {"diagnose " + data() + " --backend nope", "--backend"},
      {"cosim --scenario block5 --backend ref", "a core to compare with bittrue"},
      {"cosim --scenario block5 --seed -1", "a seed"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const RunResult r = run_rheo(c.args + " --out " + path("out"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output.rfind("rheo: error: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(c.words), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("e+308"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("179769313486231570"), std::string::npos) << r.output;
  }
  EXPECT_EQ(run_rheo("simulate --help").status, 0);
  // A first word that is no command is named.
  const RunResult r = run_rheo("nosuchcommand --out " + path("out"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unknown command 'nosuchcommand', expected one of: simulate"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(run_rheo("scenarios --show ''").status, 2);
}

TEST_F(NothingLost, ARunThatWouldFillTheDiskIsRefusedBeforeItStarts) {
  std::string s = run_rheo("scenarios --show block5").output;
  const std::string key = "\"vtk_interval_s\":";
  const std::size_t at = s.find(key);
  ASSERT_NE(at, std::string::npos) << s;
  s.replace(at, s.find_first_of(",\n}", at) - at, key + " 1e-9");
  // At most one frame per step is written: 10,001 frames of about 41 kB (0.41 GB) over
  // block5's 10,000 steps, refused against a 0.1 GB limit (it was counted as 1e10 frames).
  const RunResult r = run_rheo("simulate --scenario " + write("tiny.json", s) +
                               " --no-plot -q --max-output-gb 0.1 --out " + path("out"));
  EXPECT_EQ(r.status, 1) << r.output;
  for (const char* w : {"would write about 0.4", "GB", "10001 VTK frames", "vtk_interval_s",
                        "at most one per step", "--max-output-gb"})
    EXPECT_NE(r.output.find(w), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("out")));
  expect_no_staging();
}

TEST_F(NothingLost, ARecordGivenTwiceOrHeldOutAsItsOwnCheckIsRefused) {
  const std::string copy = write("copy.csv", read(data()));
  RunResult r = run_rheo("fit " + data() + " " + copy + " --model-form column -q --out " + path("f"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("same record"), std::string::npos) << r.output;
  r = run_rheo("diagnose " + data() + " --holdout " + copy + " --model-form column -q --out " +
               path("d"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("held-out"), std::string::npos) << r.output;
  // The same record with one row more is still that record (it passed as new).
  std::string longer = read(data());
  if (longer.back() != '\n') longer += '\n';
  longer += "100000,0,0,\n";
  const std::string extended = write("extended.csv", longer);
  r = run_rheo("fit " + data() + " " + extended + " --model-form column -q --out " + path("f"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("samples (time, plate and force alike) of"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("f")) || fs::exists(path("d")));
}

TEST_F(NothingLost, DegenerateFieldsAreRefusedByName) {
  const std::string head = "# rheo-measurement: 1\n";
  std::ostringstream rows;
  rows << "time_s,plate_mm,force_N,surface_mm\n";
  for (int i = 0; i <= 200; ++i)
    rows << 0.1 * i << "," << std::min(0.01 * i, 1.0) << "," << std::min(0.05 * i, 5.0) << ",\n";
  struct Case {
    std::string name, text, words;
  };
  const std::vector<Case> cases = {
      {"hex.csv", head + rows.str() + "20.2,0x1p0,5,\n", "hexadecimal"},
      {"twice.csv", head + "# specimen_height_mm: 10\n# specimen_height_mm: 12\n" + rows.str(), "given again"},
      {"far.csv", head + "# specimen_height_mm: 1e9\n" + rows.str(), "specimen length in mm"},
      {"through.csv", head + "# specimen_height_mm: 10\n" + rows.str() + "20.2,10.5,5,\n",
       "the plate cannot pass through the specimen"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const RunResult r =
        run_rheo("fit " + write(c.name, c.text) + " --model-form column -q --out " + path("o"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find(c.name), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.words), std::string::npos) << r.output;
  }
  std::ostringstream table;
  table << "Time [s]\tRelaxation Modulus [Pa]\n";
  for (int i = 0; i < 50; ++i) table << 0.1 * (i + 1) << "\t" << (i == 30 ? -5.0 : 1000.0) << "\n";
  const std::string relax = write("relax.tsv", table.str());
  RunResult r = run_rheo("fit " + relax + " --model-form column -q --out " + path("o"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("positive relaxation modulus"), std::string::npos) << r.output;
  // Malformed import options are option errors (exit 2), found before any input is read.
  r = run_rheo("fit " + relax + " --strain 1e-320 --model-form column -q --out " + path("o"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--strain"), std::string::npos) << r.output;
  r = run_rheo("fit " + data() + " --geometry 1e9x10x10 --model-form column -q --out " + path("o"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--geometry"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("o")));
}

// The fitted moduli do not depend on the specimen's size (docs/data-format.md): a 0.1 mm
// specimen's forces are 1e4 times smaller than a 10 mm one's (micronewtons), and its fit
// stopped at its start values (Ceres' absolute gradient tolerance was met there).
TEST_F(NothingLost, AFitDoesNotDependOnTheScaleOfTheForces) {
  std::ostringstream table;
  table << "Time [ms]\tG(t) [kPa]\n";
  for (int i = 0; i < 100; ++i) table << 100 * i + 100 << "\t" << 10.0 * std::exp(-0.03 * i) + 2.0 << "\n";
  const std::string relax = write("relax.txt", table.str());
  std::vector<double> e1;
  for (const char* g : {"10x10x10", "0.1x0.1x0.1"}) {
    SCOPED_TRACE(g);
    const std::string out = path(std::string("o_") + g);
    const RunResult r = run_rheo("fit " + relax + " --geometry " + g + " --model-form column -q --out " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(read(out + "/fit.json"));
    EXPECT_GT(j["r_squared"].get<double>(), 0.9) << j.dump();
    EXPECT_GT(j["iterations"].get<int>(), j["starts"].get<int>()) << "stopped at the starts";
    for (const auto& p : j["params"]) {
      if (p["name"] == "E1_Pa") e1.push_back(p["value"].get<double>());
    }
  }
  ASSERT_EQ(e1.size(), 2u);
  // The two optima agree to well inside E1's interval (about +-2 %).
  EXPECT_NEAR(e1[1] / e1[0], 1.0, 5e-3);
}

TEST_F(NothingLost, AFitThatExplainsLittleSaysSoBesideItsIntervals) {
  // A push and hold whose force is noise about a constant: nothing for the model to explain.
  std::ostringstream s;
  s << "# rheo-measurement: 1\ntime_s,plate_mm,force_N,surface_mm\n";
  std::uint32_t seed = 12345;
  for (int i = 0; i <= 600; ++i) {
    seed = seed * 1664525u + 1013904223u;
    const double noise = (static_cast<double>(seed >> 8) / 16777216.0 - 0.5) * 2.0;
    s << 0.1 * i << "," << std::min(0.02 * i, 2.0) << "," << 3.0 + noise << ",\n";
  }
  const RunResult r =
      run_rheo("fit " + write("noise.csv", s.str()) + " --model-form column -q --out " + path("o"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the fit explains little"), std::string::npos) << r.output;
  const nlohmann::json j = nlohmann::json::parse(read(path("o/fit.json")));
  EXPECT_TRUE(j["quality_warning"].is_string()) << j.dump(2);
  EXPECT_LT(j["r_squared"].get<double>(), 0.5);
}

}  // namespace

namespace {

TEST_F(NothingLost, TheObjectModelFailingIsAnErrorUnlessTheFallbackIsAskedFor) {
  // A relaxation table over ten decades on a log axis: its fast relaxation over its long end
  // needs more explicit steps than the object model's limit (as the fish-muscle record).
  std::ostringstream s;
  s << "Time [s]\tRelaxation Modulus [Pa]\n";
  for (int i = 0; i < 400; ++i) {
    const double t = 1e-3 * std::pow(10.0, 10.0 * i / 399.0);
    s << t << "\t" << 1000.0 * std::exp(-t / 0.01) + 2000.0 * std::exp(-t / 1e5) + 500.0 << "\n";
  }
  const std::string table = write("long.tsv", s.str());
  RunResult r = run_rheo("fit " + table + " -q --out " + path("o"));
  EXPECT_EQ(r.status, 1) << r.output;
  for (const char* w : {"the object model could not run these data", "--column-fallback",
                        "--model-form column"})
    EXPECT_NE(r.output.find(w), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("o")));
  r = run_rheo("fit " + table + " -q --column-fallback --out " + path("o"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the object model could not run these data"), std::string::npos)
      << r.output;
  // Too few samples fail every model form alike: no way out through the column is offered.
  std::ostringstream few;
  few << "# rheo-measurement: 1\ntime_s,plate_mm,force_N,surface_mm\n";
  for (int i = 1; i <= 6; ++i) few << 0.5 * i << "," << 0.1 * i << "," << 0.3 * i << ",\n";
  r = run_rheo("fit " + write("few.csv", few.str()) + " -q --out " + path("o2"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("samples for the 3 parameters"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("--model-form column"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("--column-fallback"), std::string::npos) << r.output;
}

}  // namespace
