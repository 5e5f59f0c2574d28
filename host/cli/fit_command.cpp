// `rheo fit FILE... --model NAME --out DIR`: identify the specimen model's parameters.
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/backend_check_output.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/import_options.hpp"
#include "host/identify/diagnose.hpp"
#include "host/identify/fit.hpp"
#include "host/identify/measurement.hpp"
#include "host/output/staged_directory.hpp"
#include "sim/error.hpp"

namespace rheo::cli {

void register_fit(CLI::App& app) {
  struct Args {
    std::vector<std::string> files;
    std::string model = "three_element";
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
      "fit",
      "Fit the object model of the specimen (the project's particle model built from the "
      "file's geometry, run by the reference simulator under each file's plate_mm history; "
      "--model-form column for the fast 1-D first guess) to force_N (and surface_mm where "
      "present) with Ceres; writes DIR/fit.json (values, 95 % intervals, bound and identifiability "
      "flags, "
      "assumptions) and DIR/fit_*.png.\n"
      "Files: measurement CSV, relaxation-modulus tables, rheometer step-strain exports; the "
      "test type is recognised from the column names and units, flow curves, frequency sweeps "
      "and creep tests are refused. Formats, assumptions and outputs: docs/data-format.md.");
  cmd->add_option("files", args->files, "measurement files")->required()->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model,
                  "three_element or one extension: " + identify::extension_names())
      ->check(parsed_by([](const std::string& t) { identify::extension_from_name(t); }, "MODEL"))
      ->capture_default_str();
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
    std::vector<Measurement> data;
    for (const auto& f : args->files) data.push_back(load_any(f, import));
    for (const auto& m : data) std::cout << "input " << describe_import(m);
    refuse_duplicate_records(data);
    output::StagedDirectory out = stage_output(args->output);
    FitOptions options;
    options.simulation.max_dt = args->max_dt;
    options.simulation.cpu = cpu_options(args->cpu);
    apply_specimen_options(args->specimen, options.simulation);
    // Fits have no fixed length: the display counts solver iterations against their limit.
    Progress progress("fit", 0, progress_enabled(args->quiet));
    options.progress = [&progress](const FitProgress& p) {
      progress.stage(p.model + ": start " + std::to_string(p.start) + " of " +
                     std::to_string(p.starts) + ", iteration " + std::to_string(p.iteration) +
                     " of at most " + std::to_string(p.max_iterations));
    };
    const ModelSpec spec = model_spec(extension_from_name(args->model), data_scales(data));
    FitResult r;
    try {
      r = fit_model(data, spec, {}, options);
    } catch (const ObjectModelError& e) {
      column_fallback_or_throw(args->specimen, e, options.simulation, "fits");
      r = fit_model(data, spec, {}, options);
    }
    progress.finish();
    write_fit(out.path(), r, data, options);
    const std::string check_error = run_backend_checks(check_engine.get(), args->check, data, {&r},
                                                       options.simulation, out.path());
    out.commit();
    std::cout << "model " << spec.name() << ": rmse " << r.rmse_force_N << " N, R^2 "
              << r.r_squared << ", AIC " << r.aic << "\n";
    // Beside the intervals, what they are worth.
    if (!r.quality_warning().empty()) std::cout << "warning: " << r.quality_warning() << "\n";
    for (const auto& e : r.estimates) {
      std::cout << "  " << e.name << " = " << e.value;
      if (e.ci_low) std::cout << "  [" << *e.ci_low << ", " << *e.ci_high << "]";
      if (!e.unidentifiable.empty()) std::cout << "  NOT IDENTIFIABLE";
      std::cout << "\n";
    }
    std::cout << unidentifiable_warnings(r);
    std::cout << "wrote " << out.target() << "/fit.json\n";
    // The fit is kept (written above); the failed check still makes the command fail.
    if (!check_error.empty()) throw Error(check_error);
  });
}

}  // namespace rheo::cli
