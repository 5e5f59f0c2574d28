// `rheo diagnose FIT.csv [--holdout H.csv ...] --out DIR`: name what the three-element
// model gets wrong, extend it and measure the gain on held-out data (design.md §7).
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/commands.hpp"
#include "host/identify/diagnose.hpp"
#include "host/identify/measurement.hpp"

namespace rheo::cli {

void register_diagnose(CLI::App& app) {
  struct Args {
    std::vector<std::string> files;
    std::vector<std::string> holdout;
    std::string out;
    double max_dt = 0.1;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose",
      "Fit the baseline three-element model, analyse residuals by phase, fit each candidate "
      "extension (second_relaxation_time, force_dependent_damping, strain_hardening, "
      "sensor_lag, sensor_offset), pick by AIC confirmed on held-out data; writes "
      "DIR/diagnosis.json, DIR/report.md and plots.");
  cmd->add_option("files", args->files, "measurement files to fit")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--holdout", args->holdout, "held-out measurement files")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--max-dt", args->max_dt, "largest time step of the specimen model [s]")
      ->capture_default_str();
  cmd->callback([args]() {
    using namespace rheo::identify;
    std::vector<Measurement> fit_data, holdout;
    for (const auto& f : args->files) fit_data.push_back(load_any(f));
    for (const auto& f : args->holdout) holdout.push_back(load_any(f));
    DiagnoseOptions options;
    options.fit.simulation.max_dt = args->max_dt;
    const Diagnosis d = diagnose(fit_data, holdout, options);
    write_diagnosis(args->out, d, fit_data, holdout, options);
    const auto j = diagnosis_json(d);
    std::cout << "finding: " << j["finding"]["cause"].get<std::string>() << "\n"
              << "evidence: " << d.evidence << "\n"
              << "gain: holdout_rmse_ratio " << j["gain"]["holdout_rmse_ratio"].dump()
              << ", delta_aic " << j["gain"]["delta_aic"].dump() << "\n"
              << "diagnosis took " << d.seconds << " s; wrote " << args->out
              << "/diagnosis.json and " << args->out << "/report.md\n";
  });
}

}  // namespace rheo::cli
