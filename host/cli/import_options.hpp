// The options `rheo fit` and `rheo diagnose` share for imported tables (--geometry,
// --strain, --as), declared once so both commands say the same thing.
#pragma once

#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "host/backend/backend.hpp"
#include "host/cli/cli_options.hpp"

#include "host/identify/measurement.hpp"
#include "host/identify/specimen.hpp"
#include "sim/error.hpp"

namespace rheo::cli {

inline void add_import_options(CLI::App* cmd, std::string& geometry, std::string& strain,
                               std::string& as) {
  cmd->add_option("--geometry", geometry,
                  "specimen HxWxD in mm (height x width x depth) assumed for imported tables "
                  "(default 10x10x10); refused for a measurement CSV, which states its own")
      ->check(parsed_by([](const std::string& t) { identify::parse_geometry(t); }, "HxWxD"));
  cmd->add_option("--strain", strain,
                  "step strain put on a relaxation-modulus table: a fraction (0.01) or a "
                  "percentage (1%); default 1%; refused for step-strain exports (they have a "
                  "strain column) and measurement CSVs")
      ->check(parsed_by([](const std::string& t) { identify::parse_strain(t); }, "STRAIN"));
  cmd->add_option("--as", as,
                  "confirm what a table without recognisable column names holds: "
                  "relaxation_table (column 1 time [s], column 2 relaxation modulus [Pa])")
      ->check(CLI::IsMember({"relaxation_table"}));
}

// Turns the option strings into import options; throws rheo::Error on a malformed value.
inline identify::ImportOptions import_options(const std::string& geometry,
                                              const std::string& strain, const std::string& as) {
  identify::ImportOptions o;
  if (!geometry.empty()) o.geometry = identify::parse_geometry(geometry);
  if (!strain.empty()) o.strain = identify::parse_strain(strain);
  o.as = as;
  return o;
}

// Which specimen model fit and diagnose run (--model-form, --mesh).
struct SpecimenArgs {
  std::string form = "object";
  std::string mesh = "2d:auto";
  bool column_fallback = false;  // --column-fallback
};

// --backend/--lanes of fit and diagnose: where the fitted model is run again afterwards.
struct BackendCheckArgs {
  std::string backend = "ref";
  int lanes = 1;
};

inline void add_backend_check_options(CLI::App* cmd, BackendCheckArgs& a) {
  cmd->add_option("--backend", a.backend,
                  "after the fit, run the fitted model(s) on this backend too and report the "
                  "plate force against the reference (DIR/backend_check.json): " +
                      backend::backend_names() + "; ref (the default) skips the check")
      ->check(backend_spec())
      ->capture_default_str();
  cmd->add_option("--lanes", a.lanes, "lanes of the in-process fixed-point core of --backend")
      ->check(CLI::IsMember({1, 2, 4}))
      ->capture_default_str();
}

inline void add_specimen_options(CLI::App* cmd, SpecimenArgs& a) {
  cmd->add_option("--model-form", a.form,
                  "object: the project's particle model of the specimen run by the reference "
                  "simulator (default); column: a 1-D two-particle column, a fast first guess "
                  "that is not the object users simulate")
      ->check(CLI::IsMember({"object", "column"}))
      ->capture_default_str();
  cmd->add_option("--mesh", a.mesh,
                  "object model mesh: 2d:auto (3 layers, square cells), 2d:NXxNZ or "
                  "3d:NXxNYxNZ, optionally :truss (docs/identify.md)")
      ->check(parsed_by([](const std::string& t) { identify::parse_object_mesh(t); }, "MESH"))
      ->capture_default_str();
  cmd->add_flag("--column-fallback", a.column_fallback,
                "when the object model cannot run these data, use the 1-D column first guess "
                "instead (said in the output); without it that is an error");
}

// The object model failed on the data (`e`): an error naming the way out, unless the user
// asked for the column's first guess (--column-fallback), which is then said out loud on
// stderr and `o` switched to it.
inline void column_fallback_or_throw(const SpecimenArgs& a, const rheo::Error& e,
                                     identify::SimulationOptions& o, const std::string& doing) {
  if (o.form != identify::SpecimenForm::kObject) throw e;
  if (!a.column_fallback) {
    throw rheo::Error(std::string("the object model could not run these data: ") + e.what() +
                      ". --model-form column " + doing +
                      " with the 1-D column first guess instead; --column-fallback does so "
                      "whenever the object model fails");
  }
  std::cerr << "warning: the object model could not run these data (" << e.what() << "); "
            << doing << " with the 1-D column first guess instead (--column-fallback)\n";
  o.form = identify::SpecimenForm::kColumn;
}

// Applies the specimen options; throws rheo::Error on a malformed --mesh.
inline void apply_specimen_options(const SpecimenArgs& a, identify::SimulationOptions& o) {
  o.form = a.form == "column" ? identify::SpecimenForm::kColumn : identify::SpecimenForm::kObject;
  o.mesh = identify::parse_object_mesh(a.mesh);
}

}  // namespace rheo::cli
