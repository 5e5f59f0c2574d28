// `rheo cosim`: runs the RTL core (Verilator) and the bit-true model on identical frames,
// compares every particle state word and plate-force word at every step, runs the double
// reference alongside and writes DIR/cosim.json.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hls/fixed_format.hpp"
#include "host/cli/commands.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#ifdef RHEO_HAVE_RTL
#include "host/driver/cosim.hpp"
#endif

namespace rheo::cli {
namespace {

struct CosimArgs {
  std::string scenario;
  long steps = 0;
  int lanes = 1;
  std::string trace;
  long trace_steps = 100;
  std::string out;
  int compare_every = 1;
  bool quiet = false;
  bool maxwell_arm = false;
};

void run(const CosimArgs& args) {
#ifndef RHEO_HAVE_RTL
  (void)args;
  throw Error("cosim: this rheo was built without the RTL model (RHEO_WITH_RTL=OFF)");
#else
  namespace fs = std::filesystem;
  const Scenario scenario = load_scenario(args.scenario);
  driver::CosimOptions opt;
  opt.steps = args.steps > 0 ? args.steps : scenario.default_steps();
  opt.lanes = args.lanes;
  opt.trace_fst = args.trace;
  opt.trace_steps = args.trace_steps;
  opt.compare_every = args.compare_every;
  opt.maxwell_arm = args.maxwell_arm;
  const bool show = !args.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  if (show) {
    opt.progress = [&](long step) {
      if (step % 200 != 0 && step != opt.steps) return;
      const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << "\rcosim: step " << step << "/" << opt.steps << " (" << int(step / s)
                << " steps/s)   " << std::flush;
    };
  }
  fs::create_directories(args.out);
  const driver::CosimResult r = driver::run_cosim(scenario, opt);
  if (show) std::cerr << "\n";

  nlohmann::json j;
  j["scenario"] = scenario.name;
  j["steps"] = r.steps;
  j["lanes"] = r.lanes;
  j["mismatches"] = r.mismatches;
  j["first_mismatches"] = nlohmann::json::array();
  for (const auto& m : r.first) j["first_mismatches"].push_back(m.describe());
  j["max_pos_err_rel"] = r.max_pos_err_rel;
  j["rms_pos_err_rel"] = r.rms_pos_err_rel;
  j["final_max_pos_err_rel"] = r.final_max_pos_err_rel;
  j["max_force_err_rel"] = r.max_force_err_rel;
  j["max_force_ref_N"] = r.max_force_ref_N;
  j["cycles_per_step_measured"] = r.cycles_per_step_measured;
  j["cycles_per_step_formula"] = r.cycles_per_step_formula;
  j["cycles_per_step_formula_text"] = "max(ceil(E/lanes),1) + " +
                                       std::to_string(hls::kTemDrainCycles) + " + G + " +
                                       std::to_string(hls::kMpmDrainCycles) +
                                       ", G = max over lanes of sum max(degree,1)";
  j["sim_cycles"] = r.sim_cycles;
  j["sim_cycles_per_s"] = r.sim_cycles_per_s;
  j["particles"] = r.particles;
  j["edges"] = r.edges;
  j["gather_rows"] = r.gather_rows;
  j["length_unit_m"] = r.length_unit_m;
  j["force_unit_N"] = r.force_unit_N;
  j["dt_s"] = r.dt_s;
  j["compare_every_steps"] = opt.compare_every;
  j["reference_features_dropped"] = r.dropped_features;
  if (!args.trace.empty()) {
    j["trace"] = args.trace;
    j["trace_steps"] = args.trace_steps == 0 ? r.steps : std::min(args.trace_steps, r.steps);
  }
  std::ofstream(fs::path(args.out) / "cosim.json") << j.dump(2) << "\n";

  std::cout << "cosim " << scenario.name << ": " << r.steps << " steps, " << r.lanes
            << " lane(s), mismatches " << r.mismatches << "\n"
            << "  fixed vs double: max position error " << r.max_pos_err_rel
            << " of the object size (RMS " << r.rms_pos_err_rel << "), plate force error "
            << r.max_force_err_rel << " of the peak\n"
            << "  cycles per step: measured " << r.cycles_per_step_measured << ", formula "
            << r.cycles_per_step_formula << "; Verilator " << r.sim_cycles_per_s << " cycles/s\n"
            << "  wrote " << (fs::path(args.out) / "cosim.json").string() << "\n";
  if (r.mismatches > 0) {
    std::cerr << "cosim: first mismatch at " << r.first.front().describe() << "\n";
    throw Error("cosim: RTL and bit-true model differ (" + std::to_string(r.mismatches) +
                " words)");
  }
#endif
}

}  // namespace

void register_cosim(CLI::App& app) {
  auto args = std::make_shared<CosimArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cosim",
      "Run the RTL core (Verilator) and the bit-true fixed-point model on identical input, "
      "check every particle state word and plate-force word for equality at every step, "
      "compare with the double reference model and write DIR/cosim.json.");
  cmd->add_option("--scenario", args->scenario, "built-in scenario name or JSON file")->required();
  cmd->add_option("--steps", args->steps, "number of steps (default: the scenario's duration)");
  cmd->add_option("--lanes", args->lanes, "TEM/MPM lanes of the core (1 or 2)")
      ->check(CLI::Range(1, 2));
  cmd->add_option("--trace", args->trace,
                  "write an FST waveform to this file (open with scripts/rheo_core.gtkw)");
  cmd->add_option("--trace-steps", args->trace_steps,
                  "steps covered by the waveform, from the start (default 100, 0 = all: about "
                  "0.8 MB per step on block5)");
  cmd->add_option("--compare-every", args->compare_every,
                  "read back and compare the RTL particle state every K steps (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_flag("--quiet", args->quiet, "no progress on stderr");
  cmd->add_flag("--maxwell-arm", args->maxwell_arm,
                "run the core variant with the parallel Maxwell arm (MaxwellArm = 1, 1 lane): "
                "the scenario's k2/c3 arm is computed instead of dropped");
  cmd->callback([args]() { run(*args); });
}

}  // namespace rheo::cli
