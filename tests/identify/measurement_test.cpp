#include "host/identify/measurement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "sim/error.hpp"
#include "tests/test_paths.hpp"

namespace rheo::identify {
namespace {

const std::string kShared = RHEO_SHARED_DIR;
// The outside data sets live beside the checkout, never in it: without them these tests
// have nothing to read and say so instead of failing.
#define SKIP_WITHOUT_SHARED_DATA()                                                   \
  if (!std::filesystem::exists(kShared + "/data/real")) {                            \
    GTEST_SKIP() << kShared << "/data/real is not beside this checkout";            \
  }
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

// --- Imports: recognised, converted, assumptions stated ----------------------------------

// UTF-16 LE with byte-order mark, as the rheometer writes its exports (UTF-8 input of at
// most two bytes per character, e.g. the middle dot of "mN·m").
std::string utf16(const std::string& text) {
  std::string bytes = "\xFF\xFE";
  for (std::size_t i = 0; i < text.size(); ++i) {
    unsigned cp = static_cast<unsigned char>(text[i]);
    if ((cp & 0xE0) == 0xC0 && i + 1 < text.size()) {
      cp = ((cp & 0x1F) << 6) | (static_cast<unsigned char>(text[++i]) & 0x3F);
    }
    bytes.push_back(static_cast<char>(cp & 0xFF));
    bytes.push_back(static_cast<char>(cp >> 8));
  }
  return bytes;
}

std::string load_error(const std::string& path, const ImportOptions& o = {}) {
  return error_of([&] { load_any(path, o); });
}

// The words a refusal must contain: where, what was recognised, what is accepted.
void expect_refusal(const std::string& msg, const std::string& where, const std::string& test,
                    const std::vector<std::string>& recognised) {
  EXPECT_NE(msg.find(where), std::string::npos) << msg;
  EXPECT_NE(msg.find(test), std::string::npos) << msg;
  for (const auto& r : recognised) EXPECT_NE(msg.find(r), std::string::npos) << r << "\n" << msg;
  EXPECT_NE(msg.find("accept"), std::string::npos) << msg;
  EXPECT_NE(msg.find("relaxation_table"), std::string::npos) << msg;
}

TEST(RelaxationImport, FishMuscleTableBecomesAStepStrainExperimentWithStatedAssumptions) {
  SKIP_WITHOUT_SHARED_DATA();
  const Measurement m = load_any(kShared + "/data/real/fish_muscle_relaxation.tsv");
  ASSERT_EQ(m.size(), 566u);
  EXPECT_DOUBLE_EQ(m.time_s[0], 0.0139);
  const Geometry g = default_import_geometry();
  const double strain = default_import_strain();
  // force = G * strain * area: 33600 Pa * 1 % * 1e-4 m^2.
  EXPECT_NEAR(m.force_N[0], 33600.0 * strain * g.area_m2(), 1e-12);
  EXPECT_DOUBLE_EQ(m.plate_mm[100], strain * g.height_mm);
  EXPECT_EQ(m.import.test_type, "relaxation_table");
  EXPECT_NE(m.import.geometry_source.find("assumed default 10 mm cube"), std::string::npos);
  EXPECT_NE(m.import.strain_source.find("assumed default"), std::string::npos);
  ASSERT_TRUE(m.import.strain.has_value());
  EXPECT_DOUBLE_EQ(*m.import.strain, 0.01);
  // No units in the file: what was taken is said.
  EXPECT_NE(m.import.units.find("\"Time\" taken as s"), std::string::npos) << m.import.units;
  EXPECT_NE(m.import.modulus_conversion.find("does not say"), std::string::npos);
  const std::string text = describe_import(m);
  for (const char* w : {"relaxation_table", "10 x 10 x 10 mm", "--geometry", "1 % step", "--strain",
                        "modulus conversion", "units"}) {
    EXPECT_NE(text.find(w), std::string::npos) << w << "\n" << text;
  }
}

TEST(RelaxationImport, GeometryAndStrainOptionsAreAppliedAndStated) {
  const std::string path = temp_file("relax_opts.tsv",
                                     "Time [s]\tRelaxation Modulus [Pa]\n0.1\t1000\n0.2\t900\n"
                                     "0.4\t850\n");
  ImportOptions o;
  o.geometry = parse_geometry("5x20x30");
  o.strain = parse_strain("2%");
  const Measurement m = load_any(path, o);
  EXPECT_DOUBLE_EQ(m.geometry.height_mm, 5.0);
  EXPECT_DOUBLE_EQ(m.geometry.depth_mm, 30.0);
  EXPECT_DOUBLE_EQ(m.plate_mm[0], 0.02 * 5.0);
  EXPECT_NEAR(m.force_N[1], 900.0 * 0.02 * 20e-3 * 30e-3, 1e-12);
  EXPECT_EQ(m.import.geometry_source, "--geometry");
  EXPECT_EQ(m.import.strain_source, "--strain");
  EXPECT_NE(m.import.units.find("from the file"), std::string::npos) << m.import.units;
}

TEST(RelaxationImport, UnitsInTheHeaderAreConverted) {
  const std::string path =
      temp_file("relax_units.csv", "time (ms),G(t) (kPa)\n10,2.5\n20,2.0\n40,1.5\n");
  const Measurement m = load_any(path);
  EXPECT_DOUBLE_EQ(m.time_s[1], 0.02);
  const Geometry g = default_import_geometry();
  EXPECT_NEAR(m.force_N[0], 2500.0 * default_import_strain() * g.area_m2(), 1e-12);
  // "G(t)" names a shear modulus: the statement says it is used without E = 2(1 + nu) G.
  EXPECT_NE(m.import.modulus_conversion.find("E = G"), std::string::npos)
      << m.import.modulus_conversion;
}

TEST(RelaxationImport, NonNumericRowNamesLineAndField) {
  const std::string path = temp_file("relax.tsv", "Time\tG\n0.1\t100\n0.2\tabc\n0.3\t90\n");
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find(path + ":3: field 'G'"), std::string::npos) << msg;
}

TEST(RheometerImport, Utf16ExportWithDecimalCommasIsRead) {
  SKIP_WITHOUT_SHARED_DATA();
  const Measurement m = load_any(kShared + "/data/real/cnf_hydrogel_relaxation_rep2.csv");
  ASSERT_GT(m.size(), 250u);
  EXPECT_DOUBLE_EQ(m.time_s[0], 0.010);
  const Geometry g = default_import_geometry();
  EXPECT_NEAR(m.force_N[0], 7.922 * g.area_m2(), 1e-12);          // "7,922" Pa
  EXPECT_NEAR(m.plate_mm[0], 0.019 * 0.01 * g.height_mm, 1e-12);  // "0,019" %
  EXPECT_LT(m.force_N[1], 0.0);  // the instrument transient: negative stress
  EXPECT_EQ(m.import.test_type, "step_strain_export");
  EXPECT_FALSE(m.import.strain.has_value());  // the strain is the file's own
  EXPECT_NE(m.import.strain_source.find("Shear Strain"), std::string::npos);
  EXPECT_NE(m.import.modulus_conversion.find("shear stress and strain"), std::string::npos)
      << m.import.modulus_conversion;
  EXPECT_NE(m.import.recognised.find("line 4"), std::string::npos) << m.import.recognised;
  EXPECT_EQ(m.meta.at("export_Result"), "Step strain");
}

const char* kExport =
    "Test:\tx\r\nResult:\tStep strain\r\nPoint No.\tTime\tShear Strain\tShear Stress\tTorque\r\n"
    "\t\t\t\t\r\n\t[s]\t[%]\t[Pa]\t[mN\xC2\xB7m]\r\n"
    "1\t0,1\t1,0\t5,0\t0,1\r\n2\t0,2\t1,0\t\t0,1\r\n3\t0,3\t1,0\t4,0\t0,1\r\n";

TEST(RheometerImport, EmptyStressCellNamesLineAndField) {
  const std::string path = temp_file("export.csv", utf16(kExport));
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find(path + ":7: field 'Shear Stress'"), std::string::npos) << msg;
}

TEST(RheometerImport, StrainOptionIsRefusedBecauseTheFileHasAStrainColumn) {
  std::string text = kExport;
  text.replace(text.find("2\t0,2\t1,0\t\t"), 11, "2\t0,2\t1,0\t4,5\t");
  const std::string path = temp_file("export_ok.csv", utf16(text));
  EXPECT_EQ(load_any(path).size(), 3u);
  ImportOptions o;
  o.strain = 0.05;
  const std::string msg = load_error(path, o);
  EXPECT_NE(msg.find("--strain does not apply"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Shear Strain"), std::string::npos) << msg;
}

// --- Refusals ------------------------------------------------------------------------------

TEST(Refusal, RheometerFlowCurveExportIsRefusedAsAFlowCurve) {
  // The same instrument's flow-curve export: it has a stress column too, but the shear
  // rate decides.
  const std::string path = temp_file(
      "flow_export.csv",
      utf16("Test:\tHC1_flow\r\nResult:\tFlow curve\r\nPoint No.\tShear Rate\tShear Stress\t"
            "Viscosity\r\n\t[1/s]\t[Pa]\t[Pa\xC2\xB7s]\r\n1\t0,1\t12,5\t125\r\n2\t1,0\t40,1\t40,1\r\n"
            "3\t10\t101\t10,1\r\n"));
  expect_refusal(
      load_error(path), path + ":3:", "flow curve",
      {"\"Shear Rate\" [1/s] = shear rate", "\"Viscosity\" [Pa\xC2\xB7s] = viscosity", "refused"});
}

TEST(Refusal, FlowCurveTableWithUnitsInTheNamesIsRefused) {
  const std::string path =
      temp_file("flow.csv", "Shear rate (1/s),Viscosity (Pa.s)\n0.1,1000\n1,500\n10,100\n100,20\n");
  expect_refusal(load_error(path), path + ":1:", "flow curve",
                 {"\"Shear rate\" [1/s]", "\"Viscosity\" [Pa.s]"});
}

TEST(Refusal, FlowCurveIsRecognisedByItsUnitsAlone) {
  const std::string path =
      temp_file("flow_units.tsv", "x [1/s]\ty [Pa s]\n0.1\t1000\n1\t500\n10\t100\n");
  expect_refusal(load_error(path), path + ":1:", "flow curve", {"(by its unit)"});
}

TEST(Refusal, FrequencySweepIsRefused) {
  const std::string path =
      temp_file("sweep.tsv",
                "Angular Frequency [rad/s]\tStorage Modulus [Pa]\tLoss Modulus [Pa]\n"
                "0.1\t1200\t300\n1\t1500\t380\n10\t1900\t520\n");
  expect_refusal(load_error(path), path + ":1:", "frequency sweep",
                 {"= frequency", "= storage modulus", "= loss modulus"});
}

TEST(Refusal, CreepTestIsRefused) {
  const std::string path = temp_file(
      "creep.csv", "Time [s];Creep Compliance [1/Pa]\n0,5;1,0e-4\n1,0;1,6e-4\n10;2,9e-4\n");
  expect_refusal(load_error(path), path + ":1:", "creep test",
                 {"\"Time\" [s] = time", "= compliance"});
}

TEST(Refusal, TableWithoutColumnNamesIsRefusedUnlessConfirmed) {
  const std::string path = temp_file("bare.txt", "0.1 1000\n0.2 900\n0.4 850\n0.8 820\n");
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find(path + ":1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("without column names"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--as relaxation_table"), std::string::npos) << msg;
  ImportOptions o;
  o.as = "relaxation_table";
  const Measurement m = load_any(path, o);
  EXPECT_EQ(m.size(), 4u);
  EXPECT_EQ(m.import.test_type, "relaxation_table");
  EXPECT_NE(m.import.recognised.find("confirmed by --as"), std::string::npos);
  EXPECT_NE(m.import.units.find("taken as s"), std::string::npos);
}

TEST(Refusal, AsCannotTurnANamedFlowCurveIntoARelaxationTable) {
  const std::string path =
      temp_file("flow_as.tsv", "Shear Rate [1/s]\tViscosity [Pa s]\n0.1\t1000\n1\t500\n10\t90\n");
  ImportOptions o;
  o.as = "relaxation_table";
  const std::string msg = load_error(path, o);
  EXPECT_NE(msg.find("contradicts"), std::string::npos) << msg;
  EXPECT_NE(msg.find("flow curve"), std::string::npos) << msg;
  o.as = "flow_curve";
  EXPECT_NE(load_error(path, o).find("only relaxation_table"), std::string::npos);
}

TEST(Refusal, UnrecognisedColumnNamesAreListed) {
  const std::string path = temp_file("odd.csv", "alpha,beta\n1,2\n2,3\n3,4\n");
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find("not recognised"), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"alpha\" (no unit) = not recognised"), std::string::npos) << msg;
}

TEST(Refusal, MeasurementCsvWithoutItsFirstLineGetsAHint) {
  std::string text = kGood;
  text.erase(0, text.find('\n') + 1);
  text = text.substr(text.find("time_s"));
  const std::string msg = load_error(temp_file("nover2.csv", text));
  EXPECT_NE(msg.find("without its first line"), std::string::npos) << msg;
}

TEST(Refusal, NameAndUnitThatContradictEachOtherAreAnError) {
  const std::string path = temp_file("conflict.tsv", "Time [1/s]\tG [Pa]\n1\t2\n2\t3\n3\t4\n");
  const std::string msg = load_error(path);
  EXPECT_NE(msg.find(path + ":1: column 'Time' is named like time but its unit [1/s]"),
            std::string::npos)
      << msg;
}

TEST(TestTypes, RefusedTypesComeBeforeAcceptedOnesAndEachIsOneEntry) {
  const auto& types = test_types();
  bool seen_accepted_table = false;
  for (const auto& t : types) {
    if (t.id == "rheo_measurement") continue;
    if (t.accepted) seen_accepted_table = true;
    EXPECT_FALSE(!t.accepted && seen_accepted_table) << t.id << " comes after an accepted type";
    EXPECT_TRUE(t.accepted || !t.refusal.empty()) << t.id;
  }
  EXPECT_EQ(accepted_test_types(), "rheo_measurement, step_strain_export, relaxation_table");
}

// --- Options for imports -------------------------------------------------------------------

TEST(ImportOptions, GeometryAndStrainAreRefusedForAMeasurementCsv) {
  const std::string path = temp_file("native_opts.csv", kGood);
  ImportOptions o;
  o.geometry = Geometry{1.0, 2.0, 3.0};
  EXPECT_NE(load_error(path, o).find("--geometry does not apply"), std::string::npos);
  o = {};
  o.strain = 0.02;
  EXPECT_NE(load_error(path, o).find("--strain does not apply"), std::string::npos);
  const Measurement m = load_any(path);
  EXPECT_EQ(m.import.geometry_source, "file");
}

TEST(ImportOptions, MissingGeometryLinesOfAMeasurementCsvAreStatedAsDefaults) {
  std::string text = kGood;
  text.erase(text.find("# specimen_width_mm"), std::string("# specimen_width_mm: 80\n").size());
  const Measurement m = read_measurement_csv(temp_file("nowidth.csv", text));
  EXPECT_DOUBLE_EQ(m.geometry.width_mm, Geometry{}.width_mm);
  EXPECT_NE(m.import.geometry_source.find("default"), std::string::npos);
  EXPECT_NE(m.import.geometry_source.find("specimen_width_mm"), std::string::npos);
}

TEST(ImportOptions, GeometryAndStrainTextsAreParsedOrRefused) {
  const Geometry g = parse_geometry("10x20X30");
  EXPECT_DOUBLE_EQ(g.height_mm, 10.0);
  EXPECT_DOUBLE_EQ(g.width_mm, 20.0);
  EXPECT_DOUBLE_EQ(g.depth_mm, 30.0);
  for (const char* bad : {"10x20", "0x1x1", "axbxc", "1x1x1x1", "-1x2x2"}) {
    EXPECT_NE(error_of([&] { parse_geometry(bad); }).find("HxWxD"), std::string::npos) << bad;
  }
  EXPECT_DOUBLE_EQ(parse_strain("1%"), 0.01);
  EXPECT_DOUBLE_EQ(parse_strain("0.02"), 0.02);
  // A bare 1 would be 100 %: refused with the spelling that means one percent.
  EXPECT_NE(error_of([] { parse_strain("1"); }).find("'1%'"), std::string::npos);
  EXPECT_NE(error_of([] { parse_strain("150%"); }), "");
  EXPECT_NE(error_of([] { parse_strain("0"); }), "");
  EXPECT_NE(error_of([] { parse_strain("abc"); }), "");
}

TEST(LoadAny, PicksTheImporterByContent) {
  SKIP_WITHOUT_SHARED_DATA();
  EXPECT_EQ(load_any(temp_file("any.csv", kGood)).size(), 3u);
  EXPECT_GT(load_any(kShared + "/data/real/cnf_hydrogel_relaxation_rep3.csv").size(), 250u);
  EXPECT_EQ(load_any(kShared + "/data/real/fish_muscle_relaxation.tsv").size(), 566u);
}

}  // namespace
}  // namespace rheo::identify
