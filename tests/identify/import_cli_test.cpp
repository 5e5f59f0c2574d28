// `rheo fit` and `rheo diagnose` run as a user runs them, on small hand-written tables:
// refused inputs fail with what was recognised, imported ones state every assumption on the
// screen and in the JSON, unidentifiable parameters are warned about and listed, and the
// help points at the data contract in docs/.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/cli/run_rheo.hpp"
#include "tests/test_paths.hpp"

namespace {

namespace fs = std::filesystem;

using rheo::testing_support::run_rheo;
using rheo::testing_support::RunResult;

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// A fresh scratch directory per test, removed afterwards.
class ImportCli : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("rheo_import_cli_" +
             std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string file(const std::string& name, const std::string& text) const {
    const fs::path p = root_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string out() const { return (root_ / "out").string(); }

  // A relaxation test as a lab spreadsheet would hold it: time [s] and the relaxation
  // modulus [Pa] of a material with two relaxation times (0.5 s and 20 s).
  std::string relaxation_table() const {
    std::ostringstream s;
    s << "Time [s]\tRelaxation Modulus [Pa]\n";
    for (int i = 0; i < 120; ++i) {
      const double t = 0.05 * std::pow(1.05, i);
      s << t << "\t" << 1000.0 * std::exp(-t / 0.5) + 2000.0 * std::exp(-t / 20.0) << "\n";
    }
    return file("relax.tsv", s.str());
  }

  fs::path root_;
};

TEST_F(ImportCli, RelaxationTableFitStatesTheAssumedGeometryAndStrain) {
  const RunResult r = run_rheo("fit " + relaxation_table() + " --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* w : {"relaxation_table", "10 x 10 x 10 mm", "assumed default 10 mm cube",
                        "1 % step", "modulus conversion: none"}) {
    EXPECT_NE(r.output.find(w), std::string::npos) << w << "\n" << r.output;
  }
  const auto a = read_json(fs::path(out()) / "fit.json")["assumptions"];
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0]["test_type"], "relaxation_table");
  EXPECT_EQ(a[0]["geometry_mm"]["height"], 10.0);
  EXPECT_EQ(a[0]["strain"], 0.01);
}

TEST_F(ImportCli, GeometryAndStrainOptionsAreUsedAndStated) {
  const RunResult r =
      run_rheo("fit " + relaxation_table() + " --geometry 5x20x20 --strain 2% --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("geometry: 5 x 20 x 20 mm (height x width x depth), --geometry"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("2 % step, --strain"), std::string::npos) << r.output;
  const auto a = read_json(fs::path(out()) / "fit.json")["assumptions"][0];
  EXPECT_EQ(a["geometry_mm"]["height"], 5.0);
  EXPECT_EQ(a["geometry_mm"]["depth"], 20.0);
  EXPECT_EQ(a["geometry_source"], "--geometry");
  EXPECT_EQ(a["strain"], 0.02);
  EXPECT_EQ(a["strain_source"], "--strain");
}

TEST_F(ImportCli, FlowCurveIsRefusedWithWhatWasRecognised) {
  const std::string flow =
      file("flow.csv", "Shear Rate [1/s],Viscosity [Pa s]\n0.1,1000\n1,400\n10,90\n100,21\n");
  const RunResult r = run_rheo("fit " + flow + " --out " + out());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find(flow + ":1: recognised as steady-shear flow curve"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("\"Shear Rate\" [1/s] = shear rate"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("accept"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(fs::path(out()) / "fit.json"));
  const RunResult d = run_rheo("diagnose " + flow + " --out " + out());
  EXPECT_NE(d.status, 0);
  EXPECT_NE(d.output.find("flow curve"), std::string::npos) << d.output;
}

TEST_F(ImportCli, GeometryIsRefusedForAMeasurementCsvAndABareStrainOfOne) {
  const std::string clay = std::string(RHEO_SOURCE_DIR) + "/data/clay_fast.csv";
  RunResult r = run_rheo("fit " + clay + " --geometry 1x1x1 --out " + out());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--geometry does not apply to a measurement CSV"), std::string::npos)
      << r.output;
  r = run_rheo("fit " + relaxation_table() + " --strain 1 --out " + out());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("'1%'"), std::string::npos) << r.output;
}

TEST_F(ImportCli, UnidentifiableParametersAreWarnedAboutAndListed) {
  // Steady flow at 1e-3 mm/s through a 10 mm column, sampled from 40 relaxation times on:
  // the force is c2 * strain rate * area (5e5 Pa s * 1e-4 / s * 4e-4 m^2 = 0.02 N) whatever
  // E1 and c1 are. A fixed +-1e-5 N pattern stands in for noise.
  std::ostringstream s;
  s << "# rheo-measurement: 1\n# specimen_height_mm: 10\n# specimen_width_mm: 20\n"
       "# specimen_depth_mm: 20\ntime_s,plate_mm,force_N,surface_mm\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = 440.0 + i;
    s << t << "," << 1e-3 * t << "," << 0.02 + 1e-5 * ((i * 7) % 5 - 2) / 2.0 << ",\n";
  }
  // The argument above is the column's (one edge, no lateral flow): fit the column.
  const RunResult r =
      run_rheo("fit " + file("steady.csv", s.str()) + " --model-form column --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: three_element: E1_Pa"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: three_element: c1_Pa_s"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning: three_element: c2_Pa_s"), std::string::npos) << r.output;
  const auto u = read_json(fs::path(out()) / "fit.json")["unidentifiable"];
  ASSERT_EQ(u.size(), 2u) << u.dump();
  EXPECT_EQ(u[0]["param"], "E1_Pa");
  EXPECT_EQ(u[1]["param"], "c1_Pa_s");
  EXPECT_FALSE(u[0]["reason"].get<std::string>().empty());
}

TEST_F(ImportCli, DiagnoseWritesTheAssumptionsIntoDiagnosisJsonAndTheReport) {
  // The column: this test is about the stated assumptions, and it runs under the sanitizers
  // (the object model on this log-sampled table takes minutes, docs/identify.md).
  const RunResult r = run_rheo("diagnose " + relaxation_table() +
                               " --geometry 8x30x30 --model-form column --out " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("geometry: 8 x 30 x 30 mm"), std::string::npos) << r.output;
  const auto j = read_json(fs::path(out()) / "diagnosis.json");
  for (const char* k : {"baseline", "finding", "extended", "gain", "candidates"}) {
    EXPECT_TRUE(j.contains(k)) << k;
  }
  ASSERT_EQ(j["assumptions"].size(), 1u);
  EXPECT_EQ(j["assumptions"][0]["geometry_mm"]["height"], 8.0);
  EXPECT_EQ(j["assumptions"][0]["strain_source"], "assumed default; set it with --strain");
  EXPECT_TRUE(j["baseline"]["unidentifiable"].is_array());
  std::ifstream report(fs::path(out()) / "report.md");
  std::stringstream text;
  text << report.rdbuf();
  EXPECT_NE(text.str().find("## Inputs and assumptions"), std::string::npos);
  EXPECT_NE(text.str().find("8 x 30 x 30 mm (--geometry)"), std::string::npos) << text.str();
}

TEST_F(ImportCli, HelpPointsAtTheDataContractInDocs) {
  for (const char* cmd : {"fit", "diagnose"}) {
    const RunResult r = run_rheo(std::string(cmd) + " --help");
    EXPECT_EQ(r.status, 0);
    for (const char* w : {"docs/data-format.md", "--geometry", "--strain", "--as"}) {
      EXPECT_NE(r.output.find(w), std::string::npos) << cmd << ": " << w << "\n" << r.output;
    }
  }
}

}  // namespace
