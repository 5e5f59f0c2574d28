// `rheo cosim`: runs the RTL core (Verilator) and the bit-true model on identical frames,
// compares every particle state word and plate-force word at every step, runs the double
// reference alongside and writes DIR/cosim.json.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "hls/edge_element.hpp"
#include "hls/fixed_format.hpp"
#include "hls/sweep_format.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/output/json_text.hpp"
#include "host/output/staged_directory.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#ifdef RHEO_HAVE_RTL
#include "host/driver/core_image.hpp"
#include "host/cosim/cosim.hpp"
#endif

namespace rheo::cli {
namespace {

#ifdef RHEO_HAVE_RTL
// rheo-gtkw-filter is built beside rheo; the save file names it by its absolute path.
std::string gtkw_filter_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path filter = self.parent_path() / "rheo-gtkw-filter";
  if (ec || !fs::exists(filter))
    throw Error("cosim: rheo-gtkw-filter is not beside " + self.string() +
                " (it shows the waveform's fixed-point words in mm, m/s and N)");
  return filter.string();
}
#endif

struct CosimArgs {
  std::string scenario;
  std::optional<long long> steps;
  int lanes = hls::kDefaultLanes;
  std::string trace;
  long trace_steps = 100;
  OutputOptions output;
  int compare_every = 0;  // automatic
  bool quiet = false;
  std::string element = "auto";
  std::string dut = "rtl";
  double idle_prob = 0.0;
  double stall_prob = 0.0;
  std::uint64_t seed = 1;
};

void run(const CosimArgs& args) {
#ifndef RHEO_HAVE_RTL
  (void)args;
  throw Error("cosim: this rheo was built without the RTL model (RHEO_WITH_RTL=OFF)");
#else
  namespace fs = std::filesystem;
  const Scenario scenario = load_scenario(args.scenario);
  cosim::CosimOptions opt;
  opt.steps = args.steps ? static_cast<long>(*args.steps) : scenario.default_steps();
  opt.lanes = args.lanes;
  opt.dut = args.dut;
  const bool sweep = args.dut == "sweep" || args.dut == "sweep-bittrue";
  if (sweep && args.lanes != hls::kDefaultLanes)
    throw Error("cosim: --lanes " + std::to_string(args.lanes) +
                ": the sweep core has its own lanes (five; its image says how many a model uses)");
  opt.input_idle_prob = args.idle_prob;
  opt.output_stall_prob = args.stall_prob;
  opt.seed = args.seed;
  opt.trace_steps = args.trace_steps;
  opt.compare_every = args.compare_every;
  opt.element = args.element;
  output::StagedDirectory out = stage_output(args.output);
  // The waveform and its save file follow the rule of --out: inside it they are staged with
  // the rest; elsewhere they are staged beside their place, refused if they exist (unless
  // --force) or are an input, and moved into place with the results.
  opt.trace_fst =
      args.trace.empty()
          ? ""
          : out.stage_file(args.trace, {fs::path(args.trace).replace_extension(".gtkw").string()});
  opt.check_trace_size = [&args](double bytes, const std::string& breakdown) {
    check_output_budget(args.output, bytes, breakdown + "; --trace-steps traces fewer");
  };
  Progress progress("step", opt.steps, progress_enabled(args.quiet));
  opt.progress = [&progress](long step) { progress.update(step); };
  const cosim::CosimResult r = cosim::run_cosim(scenario, opt);
  progress.finish();

  nlohmann::json j;
  j["scenario"] = scenario.name;
  j["steps"] = r.steps;
  j["lanes"] = r.lanes;
  j["core_under_test"] = r.dut_name;
  j["golden_core"] = r.golden_name;
  j["input_idle_prob"] = opt.input_idle_prob;
  j["output_stall_prob"] = opt.output_stall_prob;
  j["seed"] = opt.seed;
  j["mismatches"] = r.mismatches;
  j["first_mismatches"] = nlohmann::json::array();
  for (const auto& m : r.first) j["first_mismatches"].push_back(m.describe());
  j["max_pos_err_rel"] = r.max_pos_err_rel;
  j["rms_pos_err_rel"] = r.rms_pos_err_rel;
  j["final_max_pos_err_rel"] = r.final_max_pos_err_rel;
  j["max_force_err_rel"] = r.max_force_err_rel;
  j["max_force_ref_N"] = r.max_force_ref_N;
  if (!r.tool_force_fixed_N.empty()) {
    j["max_tool_force_err_rel"] = r.max_tool_force_err_rel;
    j["max_tool_force_err_step"] = r.max_tool_force_err_step;
    j["median_tool_force_err_rel"] = r.median_tool_force_err_rel;
    j["max_tool_force_ref_N"] = r.max_tool_force_ref_N;
  }
  j["cycles_per_step_measured"] = r.cycles_per_step_measured;
  j["cycles_per_step_formula"] = r.cycles_per_step_formula;
  j["cycles_per_step_expected"] = r.cycles_per_step_expected;
  const hls::EdgeElement* element = hls::find_edge_element(r.element);
  if (sweep) {
    j["cycles_per_step_formula_text"] =
        "max over lanes of (start delay + slots) + " + std::to_string(hls::kSweepDrainCycles) +
        "; slots = max(1, cross edges) per ghost particle + max(2, own edges) per own particle"
        "; a run command of n steps: (n - 1) x period + one step (period: host/driver/sweep_overlap)";
    j["sweep_core"] = r.dut_description;
  } else {
    j["cycles_per_step_formula_text"] =
        "max(R,1) + " +
        std::to_string(element ? element->tem_drain_cycles() : driver::kTemDrainCycles) +
        " + ceil(N/lanes) + " +
        std::to_string(element ? element->mpm_drain_cycles() : driver::kMpmDrainCycles) +
        ", R = rows of the edge schedule";
  }
  j["sim_cycles"] = r.sim_cycles;
  j["sim_cycles_per_s"] = r.sim_cycles_per_s;
  j["particles"] = r.particles;
  j["edges"] = r.edges;
  if (!sweep) {
    j["edge_rows"] = r.edge_rows;
    j["edge_bubbles"] = long(r.edge_rows) * r.lanes - r.edges;
  }
  j["length_unit_m"] = r.length_unit_m;
  j["force_unit_N"] = r.force_unit_N;
  j["dt_s"] = r.dt_s;
  j["compare_every_steps"] = r.compare_every;
  j["compare_every_automatic"] = opt.compare_every == 0;
  // the whole state (Voigt lengths and arm extensions too) compared after the last step
  j["final_state_words_compared"] = r.final_state_words;
  if (opt.compare_every == 0) {
    j["readback_cycles"] = r.readback_cycles;
    j["first_step_cycles"] = r.step_cycles;
  }
  j["edge_element"] = r.element;
  j["reference_features_dropped"] = r.dropped_features;
  if (!args.trace.empty()) {
    j["trace"] = args.trace;
    j["trace_steps"] = args.trace_steps == 0 ? r.steps : std::min(args.trace_steps, r.steps);
  }
  const fs::path json_path = fs::path(out.path()) / "cosim.json";
  std::ofstream json_file(json_path);
  json_file << output::json_text(j) << "\n";
  if (!json_file.flush()) throw Error(json_path.string() + ": write failed");
  json_file.close();
  // The save file names the FST where it will be after the commit.
  if (!args.trace.empty()) cosim::write_trace_gtkw(r, opt, gtkw_filter_path(), args.trace);
  // A mismatch is a result too: cosim.json (and the waveform) are kept for the
  // investigation, and the command still fails.
  out.commit();

  std::cout << "cosim " << scenario.name << ": " << r.dut_name << " against " << r.golden_name
            << ", " << r.steps << " steps, " << r.lanes << " lane(s)"
            << (sweep ? " (" + std::to_string(r.dut_description.value("lanes_used", 0)) + " used)"
                      : std::string())
            << ", mismatches " << r.mismatches << "\n"
            << "  fixed vs double: max position error " << r.max_pos_err_rel
            << " of the object size (RMS " << r.rms_pos_err_rel << "), plate force error "
            << r.max_force_err_rel << " of the peak"
            << (r.tool_force_fixed_N.empty()
                    ? std::string()
                    : ", tool reaction error " + std::to_string(r.max_tool_force_err_rel) +
                          " of its peak " + std::to_string(r.max_tool_force_ref_N) + " N (at step " +
                          std::to_string(r.max_tool_force_err_step) + "; median " +
                          std::to_string(r.median_tool_force_err_rel) + ")")
            << "\n"
            << "  cycles per step: measured " << r.cycles_per_step_measured << ", formula "
            << r.cycles_per_step_formula
            << (r.cycles_per_step_expected != double(r.cycles_per_step_formula)
                    ? " alone, " + std::to_string(r.cycles_per_step_expected) +
                          " over these commands (steps overlap)"
                    : std::string())
            << "; Verilator " << r.sim_cycles_per_s << " cycles/s\n"
            << "  particle state compared every " << r.compare_every << " step(s)"
            << (opt.compare_every == 0
                    ? " (automatic: a read-back takes " + std::to_string(r.readback_cycles) +
                          " cycles, a step " + std::to_string(r.step_cycles) +
                          "; --compare-every 1 compares every step)"
                    : std::string())
            << (r.tool_force_fixed_N.empty() ? ", the plate force every step"
                                             : ", the plate force and the tool's reaction every step")
            << (r.final_state_words > 0
                    ? ", the whole state (" + std::to_string(r.final_state_words) +
                          " values: Voigt lengths and arm extensions too) after the last step\n"
                    : std::string("\n"))
            << "  wrote " << (fs::path(out.target()) / "cosim.json").string() << "\n";
  // The waveform comes last, so that its path is the last thing on the screen (also when
  // the run found a mismatch: that is when it is wanted).
  if (!args.trace.empty()) {
    const std::string gtkw = fs::path(args.trace).replace_extension(".gtkw").string();
    std::cout << "  waveform: " << args.trace << " (steps " << r.traced.front().first_step << ".."
              << r.traced.back().first_step + r.traced.back().steps - 1 << "), save file " << gtkw
              << "\n"
              << "  gtkwave " << args.trace << " " << gtkw << "\n";
  }
  if (r.mismatches > 0) {
    std::cerr << "cosim: first mismatch at " << r.first.front().describe() << "\n";
    throw Error("cosim: " + r.dut_name + " and " + r.golden_name + " differ (" +
                std::to_string(r.mismatches) + " values)");
  }
#endif
}

}  // namespace

void register_cosim(CLI::App& app) {
  auto args = std::make_shared<CosimArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cosim",
      "Run the RTL core (Verilator; or another core, --backend) and the bit-true fixed-point "
      "model on identical input, check every particle state word and plate-force word for "
      "equality at every step, compare with the double reference model and write "
      "DIR/cosim.json.");
  cmd->add_option("--scenario", args->scenario, "built-in scenario name or JSON file")->required();
  add_steps_option(cmd, args->steps, "number of steps (default: the scenario's duration)");
  add_lanes_option(cmd, args->lanes, "the core");
  CLI::Option* trace =
      cmd->add_option("--trace", args->trace,
                      "write an FST waveform to this file and a GTKWave save file beside it "
                      "(FILE.fst -> FILE.gtkw: opens on step 1, words in mm, m/s and N)")
          ->check(non_empty_name("a file name", "FILE"));
  cmd->add_option("--trace-steps", args->trace_steps,
                  "steps covered by the waveform, from the start (default 100, 0 = all: about "
                  "1.2 MB per step on block5, 20 MB on block15; the estimate counts against "
                  "--max-output-gb)")
      ->check(whole_number_in(0, kMaxSteps, "a number of steps (0: all)"))
      ->needs(trace);
  cmd->add_option("--compare-every", args->compare_every,
                  "read back and compare the particles' positions and velocities every K steps "
                  "(the plate force is compared every step, the whole state with the Voigt "
                  "lengths and arm extensions after the last step); 1 = every step; default 0 = "
                  "automatic: K = read-back cycles / one step's cycles, measured after step 1, "
                  "so reading back costs at most as much as stepping")
      ->check(whole_number_in(0, kMaxSteps, "a step interval (0: automatic)"));
  add_output_options(cmd, args->output);
  args->output.output_options.push_back("--trace");
  cmd->add_flag("--quiet,-q", args->quiet, "no progress on stderr");
  cmd->add_option("--backend", args->dut,
                  "the core under test, compared word for word with bittrue: rtl (default, "
                  "rheo_core), remote:PATH (a cosim-server's core), sweep (the sweep core, "
                  "block15 on one XC2V6000, with its board SRAM; docs/sweep_core.md) or "
                  "sweep-bittrue")
      ->capture_default_str()
      ->check(backend_spec())
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            // What a cosimulation compares with bittrue: a core, not another model.
            const bool core = text == "rtl" || text == "sweep" || text == "sweep-bittrue" ||
                              (text.rfind("remote:", 0) == 0 && text.size() > 7);
            return core ? "" : "'" + text + "': expected a core to compare with bittrue: rtl, "
                                            "remote:PATH, sweep or sweep-bittrue";
          },
          "CORE"));
  cmd->add_option("--idle-prob", args->idle_prob,
                  "rtl: probability per clock of an idle cycle on the core's input stream "
                  "(s_axis_tvalid low), default 0")
      ->check(number_in(0.0, 0.95, "a probability per clock"));
  cmd->add_option("--stall-prob", args->stall_prob,
                  "rtl: probability per clock of back-pressure on the core's output stream "
                  "(m_axis_tready low), default 0")
      ->check(number_in(0.0, 0.95, "a probability per clock"));
  cmd->add_option("--seed", args->seed, "rtl: seed of the idle and stall patterns (default 1)")
      ->check(whole_number_in(0, std::numeric_limits<long long>::max(), "a seed"));
  // auto picks the element whose core computes the scenario's edges (the Maxwell arm: the
  // three-element+arm core, 1 lane); a simpler element drops what it lacks (listed).
  add_element_option(cmd, args->element, true);
  cmd->callback([args]() { run(*args); });
}

}  // namespace rheo::cli
