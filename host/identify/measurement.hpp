// Measured experiments in the data contract of design.md §7 and importers that convert
// other formats (relaxation-modulus tables, rheometer exports) into it.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace rheo::identify {

// The specimen block the plate pushes (design.md §7 `# specimen_*_mm` keys). The fit
// model reduces it to a 1-D column of this height and top area (see specimen.hpp).
struct Geometry {
  double height_mm = 12.5;
  double width_mm = 80.0;
  double depth_mm = 80.0;
  double area_m2() const { return width_mm * depth_mm * 1e-6; }
  double height_m() const { return height_mm * 1e-3; }
};

// One experiment: a plate displacement history and what was measured under it.
// surface_mm holds NaN where no surface displacement was measured.
struct Measurement {
  std::string source;  // file it came from (for messages, reports)
  Geometry geometry;
  std::map<std::string, std::string> meta;  // every `# key: value` line, in file order by key
  std::vector<double> time_s;
  std::vector<double> plate_mm;
  std::vector<double> force_N;
  std::vector<double> surface_mm;

  std::size_t size() const { return time_s.size(); }
  bool has_surface() const;
};

// Reads a measurement CSV (design.md §7). Throws rheo::Error naming file, line and field
// for anything malformed: missing header or version line, wrong columns, non-numbers,
// non-finite values, time not strictly increasing, fewer than 3 rows, bad geometry.
Measurement read_measurement_csv(const std::string& path);

// Writes a measurement CSV (design.md §7) atomically: to a temporary file renamed into
// place, so a failed write never leaves a half-written file. Extra `#` lines in comments.
void write_measurement_csv(const std::string& path, const Measurement& m,
                           const std::vector<std::string>& comments = {});

// How a relaxation test (modulus vs time after a strain step) is turned into a plate
// history: the modulus is treated as the modulus of the 1-D column (no shear/extension
// conversion), the plate moves to strain * height at the first sample and holds, and the
// force is modulus * strain * area.
struct RelaxationImportOptions {
  Geometry geometry{10.0, 10.0, 10.0};  // assumed specimen: a 10 mm cube
  double strain = 0.01;                 // assumed step strain (1 %)
};

// Reads a two-column table (time [s], relaxation modulus [Pa]; tab, comma or space
// separated; one header line allowed) and converts it as described above.
Measurement import_relaxation_table(const std::string& path,
                                    const RelaxationImportOptions& options = {});

// Reads a rheometer step-strain export (UTF-16 LE with BOM, CRLF, tab separated, decimal
// commas, header lines, a column-name line with "Time", "Shear Strain" and "Shear
// Stress", then a units line). Shear strain [%] becomes plate_mm = strain * height and
// shear stress [Pa] becomes force_N = stress * area on the assumed geometry; rows whose
// time, strain or stress cell is empty are rejected with file/line/field.
Measurement import_rheometer_export(const std::string& path,
                                    const Geometry& geometry = {10.0, 10.0, 10.0});

// Chooses the importer by content: a `# rheo-measurement` first line -> CSV; a UTF-16
// byte-order mark -> rheometer export; otherwise a two-column relaxation table.
Measurement load_any(const std::string& path);

}  // namespace rheo::identify
