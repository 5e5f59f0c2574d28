#include "host/identify/measurement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "sim/error.hpp"

namespace rheo::identify {
namespace {

const std::string kShared = RHEO_SHARED_DIR;
// Values are written with 10 significant digits.
constexpr double kRoundTripTol = 1e-9;

std::string temp_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kGood =
    "# rheo-measurement: 1\n# specimen_height_mm: 80\n# specimen_width_mm: 80\n"
    "# specimen_depth_mm: 12.5\n# material: clay\ntime_s,plate_mm,force_N,surface_mm\n"
    "0.000,0.0000,0.0012,\n0.1,0.05,1.5,\n0.2,0.1,3.0,0.09\n";

TEST(MeasurementCsv, ReadsTheContractFormatWithEmptySurfaceCells) {
  const Measurement m = read_measurement_csv(temp_file("good.csv", kGood));
  ASSERT_EQ(m.size(), 3u);
  EXPECT_DOUBLE_EQ(m.geometry.height_mm, 80.0);
  EXPECT_DOUBLE_EQ(m.geometry.depth_mm, 12.5);
  EXPECT_DOUBLE_EQ(m.force_N[1], 1.5);
  EXPECT_TRUE(std::isnan(m.surface_mm[0]));
  EXPECT_DOUBLE_EQ(m.surface_mm[2], 0.09);
  EXPECT_EQ(m.meta.at("material"), "clay");
}

TEST(MeasurementCsv, BadNumberIsReportedWithFileLineAndField) {
  std::string text = kGood;
  text.replace(text.find("1.5"), 3, "1.x");
  const std::string path = temp_file("bad_number.csv", text);
  const std::string msg = error_of([&] { read_measurement_csv(path); });
  EXPECT_NE(msg.find(path + ":8"), std::string::npos) << msg;
  EXPECT_NE(msg.find("force_N"), std::string::npos) << msg;
}

TEST(MeasurementCsv, TimeThatDoesNotIncreaseIsRejected) {
  std::string text = kGood;
  text.replace(text.find("0.2,0.1"), 3, "0.1");
  const std::string msg = error_of([&] { read_measurement_csv(temp_file("time.csv", text)); });
  EXPECT_NE(msg.find(":9: field 'time_s'"), std::string::npos) << msg;
}

TEST(MeasurementCsv, WrongColumnHeaderIsRejected) {
  std::string text = kGood;
  text.replace(text.find("force_N"), 7, "force");
  const std::string msg = error_of([&] { read_measurement_csv(temp_file("hdr.csv", text)); });
  EXPECT_NE(msg.find("expected 'time_s,plate_mm,force_N,surface_mm'"), std::string::npos) << msg;
}

TEST(MeasurementCsv, FileWithoutVersionLineIsRejected) {
  const std::string msg = error_of([&] {
    read_measurement_csv(temp_file("nover.csv", "time_s,plate_mm,force_N,surface_mm\n"));
  });
  EXPECT_NE(msg.find("rheo-measurement"), std::string::npos) << msg;
}

TEST(MeasurementCsv, NonPositiveGeometryIsRejected) {
  std::string text = kGood;
  text.replace(text.find("height_mm: 80"), 13, "height_mm: -1");
  const std::string msg = error_of([&] { read_measurement_csv(temp_file("geo.csv", text)); });
  EXPECT_NE(msg.find(":2: field 'specimen_height_mm'"), std::string::npos) << msg;
}

TEST(MeasurementCsv, WrittenFileReadsBackTheSameValues) {
  const Measurement m = read_measurement_csv(temp_file("rt_in.csv", kGood));
  const auto out = (std::filesystem::path(::testing::TempDir()) / "rt_out.csv").string();
  write_measurement_csv(out, m, {"SYNTHETIC: test"});
  const Measurement r = read_measurement_csv(out);
  ASSERT_EQ(r.size(), m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_NEAR(r.force_N[i], m.force_N[i], kRoundTripTol);
    EXPECT_EQ(std::isnan(r.surface_mm[i]), std::isnan(m.surface_mm[i]));
  }
  EXPECT_FALSE(std::filesystem::exists(out + ".partial"));
}

TEST(RelaxationImport, FishMuscleTableBecomesAStepStrainExperiment) {
  const Measurement m = import_relaxation_table(kShared + "/data/real/fish_muscle_relaxation.tsv");
  ASSERT_EQ(m.size(), 566u);
  EXPECT_DOUBLE_EQ(m.time_s[0], 0.0139);
  const RelaxationImportOptions o;
  // force = G * strain * area: 33600 Pa * 1 % * 1e-4 m^2.
  EXPECT_NEAR(m.force_N[0], 33600.0 * o.strain * o.geometry.area_m2(), 1e-12);
  EXPECT_DOUBLE_EQ(m.plate_mm[100], o.strain * o.geometry.height_mm);
}

TEST(RelaxationImport, NonNumericRowNamesLineAndField) {
  const std::string path = temp_file("relax.tsv", "Time\tG\n0.1\t100\n0.2\tabc\n0.3\t90\n");
  const std::string msg = error_of([&] { import_relaxation_table(path); });
  EXPECT_NE(msg.find(path + ":3: field 'modulus'"), std::string::npos) << msg;
}

TEST(RheometerImport, Utf16ExportWithDecimalCommasIsRead) {
  const Measurement m =
      import_rheometer_export(kShared + "/data/real/cnf_hydrogel_relaxation_rep2.csv");
  ASSERT_GT(m.size(), 250u);
  EXPECT_DOUBLE_EQ(m.time_s[0], 0.010);
  const Geometry g{10.0, 10.0, 10.0};
  EXPECT_NEAR(m.force_N[0], 7.922 * g.area_m2(), 1e-12);          // "7,922" Pa
  EXPECT_NEAR(m.plate_mm[0], 0.019 * 0.01 * g.height_mm, 1e-12);  // "0,019" %
  EXPECT_LT(m.force_N[1], 0.0);  // the instrument transient: negative stress
}

TEST(RheometerImport, EmptyStressCellNamesLineAndField) {
  const std::string text =
      "Test:\tx\r\nPoint No.\tTime\tShear Strain\tShear Stress\r\n\t[s]\t[%]\t[Pa]\r\n"
      "1\t0,1\t1,0\t5,0\r\n2\t0,2\t1,0\t\r\n3\t0,3\t1,0\t4,0\r\n";
  std::string bytes = "\xFF\xFE";
  for (char c : text) {
    bytes.push_back(c);
    bytes.push_back('\0');
  }
  const std::string path = temp_file("export.csv", bytes);
  const std::string msg = error_of([&] { import_rheometer_export(path); });
  EXPECT_NE(msg.find(path + ":5: field 'Shear Stress'"), std::string::npos) << msg;
}

TEST(LoadAny, PicksTheImporterByContent) {
  EXPECT_EQ(load_any(temp_file("any.csv", kGood)).size(), 3u);
  EXPECT_GT(load_any(kShared + "/data/real/cnf_hydrogel_relaxation_rep3.csv").size(), 250u);
  EXPECT_EQ(load_any(kShared + "/data/real/fish_muscle_relaxation.tsv").size(), 566u);
}

}  // namespace
}  // namespace rheo::identify
