// `rheo diagnose FIT.csv [--holdout H.csv ...] --out DIR`: name what the three-element
// model gets wrong, extend it and measure the gain on held-out data (diagnosis.json and
// the cause vocabulary: docs/data-format.md).
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/backend_check_output.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/import_options.hpp"
#include "host/identify/diagnose.hpp"
#include "host/identify/measurement.hpp"
#include "host/output/staged_directory.hpp"
#include "sim/error.hpp"

namespace rheo::cli {

void register_diagnose(CLI::App& app) {
  struct Args {
    std::vector<std::string> files;
    std::vector<std::string> holdout;
    OutputOptions output;
    bool quiet = false;
    double max_dt = 0.1;
    std::string geometry, strain, as;
    SpecimenArgs specimen;
    CpuArgs cpu;
    BackendCheckArgs check;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose",
      "Fit the baseline three-element model, analyse residuals by phase, fit each candidate "
      "extension (" +
          identify::extension_names() +
          "), pick by AIC confirmed on held-out data; writes "
          "DIR/diagnosis.json, DIR/report.md and plots. Input formats, diagnosis.json and the "
          "cause vocabulary: docs/data-format.md.");
  cmd->add_option("files", args->files, "measurement files to fit")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--holdout", args->holdout, "held-out measurement files")
      ->check(CLI::ExistingFile);
  add_output_options(cmd, args->output);
  cmd->add_flag("--quiet,-q", args->quiet, "no progress display on stderr");
  add_max_dt_option(cmd, args->max_dt);
  add_cpu_options(cmd, args->cpu);
  add_import_options(cmd, args->geometry, args->strain, args->as);
  add_specimen_options(cmd, args->specimen);
  add_backend_check_options(cmd, args->check);
  cmd->callback([args]() {
    using namespace rheo::identify;
    const ImportOptions import = import_options(args->geometry, args->strain, args->as);
    const std::unique_ptr<backend::Backend> check_engine = open_check_backend(args->check);
    std::vector<Measurement> fit_data, holdout;
    for (const auto& f : args->files) fit_data.push_back(load_any(f, import));
    for (const auto& f : args->holdout) holdout.push_back(load_any(f, import));
    for (const auto& m : fit_data) std::cout << "input " << describe_import(m);
    for (const auto& m : holdout) std::cout << "held-out input " << describe_import(m);
    refuse_duplicate_records(fit_data, holdout);
    output::StagedDirectory out = stage_output(args->output);
    DiagnoseOptions options;
    options.fit.simulation.max_dt = args->max_dt;
    options.fit.simulation.cpu = cpu_options(args->cpu);
    apply_specimen_options(args->specimen, options.fit.simulation);
    Progress progress("model fits", 0, progress_enabled(args->quiet));
    options.on_model_fitted = [&progress](int done, int total) {
      progress.set_total(total);
      progress.update(done);
    };
    Diagnosis d;
    try {
      d = diagnose(fit_data, holdout, options);
    } catch (const ObjectModelError& e) {
      // The explicit object model cannot run every record (a relaxation much faster than a
      // long record needs too many steps). The specimen model is named in every output.
      column_fallback_or_throw(args->specimen, e, options.fit.simulation, "diagnoses");
      d = diagnose(fit_data, holdout, options);
    }
    progress.finish();
    write_diagnosis(out.path(), d, fit_data, holdout, options);
    std::vector<const FitResult*> fits{&d.baseline};
    if (d.chosen >= 0) fits.push_back(&d.extended());
    const std::string check_error = run_backend_checks(check_engine.get(), args->check, fit_data,
                                                       fits, options.fit.simulation, out.path());
    out.commit();
    const auto j = diagnosis_json(d);
    std::cout << "finding: " << j["finding"]["cause"].get<std::string>() << "\n"
              << "evidence: " << d.evidence << "\n"
              << "gain: holdout_rmse_ratio " << j["gain"]["holdout_rmse_ratio"].dump()
              << ", delta_aic " << j["gain"]["delta_aic"].dump() << "\n"
              << (d.mesh_change
                      ? "mesh check: force changes by " + std::to_string(100.0 * *d.mesh_change) +
                            " % on " + d.finer_mesh + "\n"
                      : std::string())
              << (d.remaining.empty() ? std::string() : "remaining: " + d.remaining + "\n")
              << unidentifiable_warnings(d.baseline)
              << (d.chosen < 0 ? std::string() : unidentifiable_warnings(d.extended()))
              << "diagnosis took " << d.seconds << " s; wrote " << out.target()
              << "/diagnosis.json and " << out.target() << "/report.md\n";
    // The fit is kept (written above); the failed check still makes the command fail.
    if (!check_error.empty()) throw Error(check_error);
  });
}

}  // namespace rheo::cli
