// Measured experiments in the project's measurement format (docs/data-format.md) and the
// importers that turn other tables (relaxation-modulus tables, rheometer step-strain
// exports) into it. Which kind of test a file holds is recognised from its column names and
// units; tests the column model cannot mean (flow curves, frequency sweeps, creep) are
// refused with a message that says what was recognised.
#pragma once

#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rheo::identify {

// The specimen block the plate pushes (docs/data-format.md, `# specimen_*_mm` keys). The
// fit model reduces it to a 1-D column of this height and top area (see specimen.hpp).
// The specimen sizes a file or --geometry may give, in mm: from a thin film between a
// rheometer's plates to a block between the platens of a large testing machine (about a
// metre of travel). Outside, a number is a unit mistake (m for mm, a 1,000 km typo), not a
// specimen; it is refused by field.
inline constexpr double kMinSpecimenMm = 1e-3;
inline constexpr double kMaxSpecimenMm = 1e3;
// The smallest step strain accepted (--strain, a step-strain export's largest strain):
// below it the step is below anything a rheometer imposes, and a subnormal or zero strain
// turns every force into rounding noise.
inline constexpr double kMinStepStrain = 1e-7;

struct Geometry {
  double height_mm = 12.5;
  double width_mm = 80.0;
  double depth_mm = 80.0;
  double area_m2() const { return width_mm * depth_mm * 1e-6; }
  double height_m() const { return height_mm * 1e-3; }
};

// What a file was recognised as and what had to be assumed to make a compression test of
// the column from it. Written into fit.json / diagnosis.json ("assumptions") and printed,
// so that no assumption is made without a word.
struct ImportInfo {
  std::string test_type = "rheo_measurement";  // an id of test_types()
  std::string recognised;                      // columns and units as read from the file
  std::string geometry_source = "file";  // "file", "default ..." or "assumed ..." or "--geometry"
  std::optional<double> strain;          // step strain (fraction) put on modulus tables
  std::string strain_source = "plate_mm column";
  std::string modulus_conversion = "none (the file holds the plate force of a compression test)";
  std::string units = "SI as the format prescribes";
};

// One experiment: a plate displacement history and what was measured under it.
// surface_mm holds NaN where no surface displacement was measured.
struct Measurement {
  std::string source;  // file it came from (for messages, reports)
  Geometry geometry;
  ImportInfo import;
  std::map<std::string, std::string> meta;  // every `# key: value` line, in file order by key
  std::vector<double> time_s;
  std::vector<double> plate_mm;
  std::vector<double> force_N;
  std::vector<double> surface_mm;

  std::size_t size() const { return time_s.size(); }
  bool has_surface() const;
};

// Noise level of a force record from its second differences (independent of any model):
// sigma = rms(f[i+1] - 2 f[i] + f[i-1]) / sqrt(6), exact for white noise on a smooth curve.
double noise_from_second_differences(const Measurement& m);

// Refuses (rheo::Error naming both files) a record given twice: the same data (time, plate,
// force and surface columns equal, whatever the file is called or how it is formatted)
// among the fit files, among the held-out files, or in both. Twice the same record doubles
// n and narrows every interval; a held-out record that is a fit record tests nothing.
void refuse_duplicate_records(const std::vector<Measurement>& fit,
                              const std::vector<Measurement>& holdout = {});

// Reads a measurement CSV (docs/data-format.md). Throws rheo::Error naming file, line and
// field for anything malformed: missing header or version line, wrong columns,
// non-numbers, non-finite values, time not strictly increasing, fewer than 3 rows, bad
// geometry.
Measurement read_measurement_csv(const std::string& path);
// The same from a stream; `path` names it in messages.
Measurement read_measurement_csv(std::istream& in, const std::string& path);

// Writes a measurement CSV (docs/data-format.md) atomically: to a temporary file renamed
// into place, so a failed write never leaves a half-written file. Extra `#` lines in
// comments.
void write_measurement_csv(const std::string& path, const Measurement& m,
                           const std::vector<std::string>& comments = {});

// What a column of an imported table measures, recognised from its name, else its unit.
enum class Quantity {
  kTime,
  kStrain,
  kStress,
  kModulus,  // relaxation modulus G(t) or E(t)
  kShearRate,
  kViscosity,
  kFrequency,
  kStorageModulus,
  kLossModulus,
  kCompliance,
  kOther,  // point number, torque, temperature, status, ... (read, not used)
};
std::string quantity_name(Quantity q);

// A kind of test a file can hold. A file is of the first type in test_types() order whose
// `all_of` quantities are all present and, when `any_of` is not empty, one of `any_of` is;
// refused types come first because one distinctive column (a shear rate, a frequency)
// decides the test whatever else the file holds. Adding a test type is one entry there.
struct TestType {
  std::string id;           // "relaxation_table", "flow_curve", ...
  std::string name;         // "stress relaxation table", ...
  std::string description;  // the columns that identify it
  std::vector<Quantity> all_of;
  std::vector<Quantity> any_of;
  bool accepted = false;
  std::string refusal;  // why the column model cannot mean it (refused types)
};
const std::vector<TestType>& test_types();
// "rheo_measurement, relaxation_table, step_strain_export": the ids that are accepted.
std::string accepted_test_types();

// Choices the user makes for imported tables (`rheo fit/diagnose --geometry --strain --as`).
struct ImportOptions {
  // Specimen assumed for an imported table (default: a 10 mm cube). Refused for a
  // measurement CSV, which carries its own `# specimen_*_mm` lines.
  std::optional<Geometry> geometry;
  // Step strain (fraction, 0 < strain < 1) put on a relaxation-modulus table (default
  // 1 %). Refused for a step-strain export (which has a strain column) and a measurement CSV.
  std::optional<double> strain;
  // Test type the user confirms for a table whose columns have no recognisable names
  // (only "relaxation_table": column 1 time [s], column 2 modulus [Pa]). Refused when the
  // columns are named and say something else.
  std::string as;
};

// The geometry and strain assumed for imported tables when the user sets none.
Geometry default_import_geometry();
double default_import_strain();

// Parses `--geometry HxWxD` (mm, e.g. "10x20x20"); throws rheo::Error saying what is wrong.
Geometry parse_geometry(const std::string& text);
// Parses `--strain`: "1%" (percent) or "0.01" (fraction); the result is a fraction in
// (0, 1). A bare number >= 1 is refused (write "1%" for one percent).
double parse_strain(const std::string& text);

// Reads any accepted file: a measurement CSV (first line `# rheo-measurement`), else a
// table (UTF-8 or UTF-16 LE with byte-order mark; tab, semicolon, comma or space
// separated; decimal commas when the separator is not a comma; `key: value` lines, a
// column-name line and an optional units line before the data) whose test type is
// recognised from its column names and units. Relaxation tables become a step-strain test
// on the assumed geometry (plate = strain * height from the first sample on, force =
// modulus * strain * area); step-strain exports become plate = strain * height and force =
// stress * area. Moduli are not converted between shear and extension (see ImportInfo).
// Throws rheo::Error with file, line and what was recognised for refused or unrecognised
// tables and for options that do not apply to the file.
Measurement load_any(const std::string& path, const ImportOptions& options = {});
// load_any on a file's bytes already in memory; `path` names it in messages. The whole
// importer, file reading aside: the fuzzer (fuzz/fuzz_measurement.cpp) calls it directly.
Measurement parse_measurement_text(const std::string& bytes, const std::string& path,
                                   const ImportOptions& options = {});

// One line per file for the screen: what it was read as and every assumption made.
std::string describe_import(const Measurement& m);

}  // namespace rheo::identify
