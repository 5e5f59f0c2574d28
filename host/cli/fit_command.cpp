// `rheo fit FILE... --model NAME --out DIR`: identify the specimen model's parameters.
#include <iostream>
#include <string>
#include <vector>

#include "host/cli/commands.hpp"
#include "host/identify/diagnose.hpp"
#include "host/identify/fit.hpp"
#include "host/identify/measurement.hpp"

namespace rheo::cli {

void register_fit(CLI::App& app) {
  struct Args {
    std::vector<std::string> files;
    std::string model = "three_element";
    std::string out;
    double max_dt = 0.1;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "fit",
      "Fit the specimen model (the reference edge kernel on a coarse column of the specimen, "
      "driven by each file's plate_mm history) to force_N (and surface_mm where present) with "
      "Ceres; writes DIR/fit.json (values, 95 % intervals, bound flags) and DIR/fit_*.png.\n"
      "Files: measurement CSV (design.md §7), relaxation-modulus tables, rheometer exports.");
  cmd->add_option("files", args->files, "measurement files")->required()->check(CLI::ExistingFile);
  cmd->add_option("--model", args->model,
                  "three_element, second_relaxation_time, force_dependent_damping, "
                  "strain_hardening, sensor_lag or sensor_offset")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--max-dt", args->max_dt, "largest time step of the specimen model [s]")
      ->capture_default_str();
  cmd->callback([args]() {
    using namespace rheo::identify;
    std::vector<Measurement> data;
    for (const auto& f : args->files) data.push_back(load_any(f));
    FitOptions options;
    options.simulation.max_dt = args->max_dt;
    const ModelSpec spec = model_spec(extension_from_name(args->model), data_scales(data));
    const FitResult r = fit_model(data, spec, {}, options);
    write_fit(args->out, r, data, options);
    std::cout << "model " << spec.name() << ": rmse " << r.rmse_force_N << " N, AIC " << r.aic
              << "\n";
    for (const auto& e : r.estimates) {
      std::cout << "  " << e.name << " = " << e.value;
      if (!e.at_bound.empty())
        std::cout << "  (at " << e.at_bound << " bound)";
      else if (e.ci_low)
        std::cout << "  [" << *e.ci_low << ", " << *e.ci_high << "]";
      std::cout << "\n";
    }
    std::cout << "wrote " << args->out << "/fit.json\n";
  });
}

}  // namespace rheo::cli
