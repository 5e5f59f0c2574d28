// `rheo synth [--lanes L] --out DIR`: Virtex-II synthesis of the TEM, the MPM and the core
// with Yosys, a resource and timing estimate, a constraints file for the vendor tools and
// the performance model (time per step on one XC2V6000 for block5 and block15).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "hls/edge_element.hpp"
#include "hls/fixed_format.hpp"
#include "hls/sweep_format.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/output/json_text.hpp"
#include "host/output/staged_directory.hpp"
#include "host/synth/delay_model.hpp"
#include "host/synth/performance_model.hpp"
#include "host/synth/rtl_sources.hpp"
#include "host/synth/sweep_performance.hpp"
#include "host/synth/yosys_runner.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using synth::Resources;

// The 2003 design (seed 000, Tables 1 and 2) for the side-by-side table.
constexpr double kPaperFpgaStepMs = 0.20;
constexpr double kPaperPcStepMs = 3.65;
constexpr int kPaperTemSlices = 4144, kPaperTemMults = 16;
constexpr int kPaperMpmSlices = 640, kPaperMpmMults = 9;
// Targets of issue 5.
constexpr double kTargetBlock15Us = 100.0;
constexpr double kTargetBlock5Us = 5.0;
constexpr double kTargetPeakFraction = 0.5;
// The reference model is timed for at least this long per scenario, so the figure is
// not dominated by timer resolution or a cold cache.
constexpr double kReferenceTimingSeconds = 1.0;
// rtl/rheo_core.sv accepts Lanes 1..4; the lane counts every backend runs are
// hls::kLaneCounts (the fit below tries those).
// The core is synthesised at block5 capacity (128 particles, 2,048 edge slots): every
// memory has at most two registered ports, so Yosys maps them to RAMB16 / LUT RAM and the
// run takes minutes (one lane: 3-7 min here). Larger capacities come from the analytic
// block RAM model (estimate_core_ramb16).
const std::vector<std::string> kCoreCapacityParams = {"MaxParticles=128", "MaxEdges=2048"};

// The model size each figure of the 2003 paper was measured on (seed 000, Table 2): its PC
// ran the 5x5x5 model, its FPGA the 15x15x16 model. A time is set beside a paper figure only
// for the same size.
constexpr const char* kPaperPcModel = "block5";
constexpr const char* kPaperFpgaModel = "block15";

struct Options {
  int lanes = hls::kDefaultLanes;
  OutputOptions output;
  bool quiet = false;
  std::vector<std::string> designs{"tem", "mpm", "core", "sweep"};
  // The sweep core's build (rtl/rheo_sweep_core.sv): lanes, slab depth, ghost depth, window.
  std::vector<int> sweep_build{5, 1024, 256, 512};
  std::string core_top = "rheo_core";
  synth::Capacity core_capacity{128, 2048};
  bool time_reference = true;
  // Another copy of rtl/ (a modified design synthesised beside the one built into rheo).
  std::string rtl_dir;
};

json resources_json(const Resources& r) {
  const synth::Utilisation u = synth::utilisation(r);
  json j = {{"lut4", r.lut4},
            {"flip_flops", r.ff},
            {"mult18x18", r.mult18},
            {"ramb16", r.ramb16},
            {"carry_muxcy", r.carry},
            {"estimated_slices", u.slices},
            {"percent_of_xc2v6000",
             {{"slices", u.slices_pct}, {"mult18x18", u.mult18_pct}, {"ramb16", u.ramb16_pct}}},
            {"cells_by_type", r.cells_by_type}};
  return j;
}

// The slowest register-to-register path of the static timing, cell by cell (arrival at
// each cell's output), so a designer can find it in the RTL.
json critical_path_json(const synth::CriticalPath& c, const synth::PathTiming& t) {
  json hops = json::array();
  for (const auto& h : c.hops) {
    hops.push_back({{"cell", h.cell},
                    {"type", h.type},
                    {"arrival_ns", h.arrival_ns},
                    {"net", h.net},
                    {"src", h.src}});
  }
  return {{"source", "static timing of the mapped netlist (host/synth/static_timing.hpp)"},
          {"period_ns", t.period_ns},
          {"logic_ns", t.logic_ns},
          {"routing_ns", t.routing_ns},
          {"limited_by", t.limited_by},
          {"cells_by_type", c.cells_by_type},
          {"timed_cells", c.timed_cells},
          {"hops", hops}};
}

json result_json(const synth::SynthResult& s) {
  json corners = json::array();
  for (const synth::TimingCorner& c : s.corners)
    corners.push_back({{"cell_delay_factor", c.cell_factor},
                       {"net_delay_factor", c.net_factor},
                       {"fmax_mhz", c.fmax_mhz},
                       {"limited_by", c.limited_by}});
  return {{"top", s.spec.top},
          {"sources", s.spec.sources},
          {"parameters", s.spec.params},
          {"yosys_seconds", s.yosys_seconds},
          {"resources", resources_json(s.resources)},
          {"longest_path",
           {{"source", "Yosys ltp: longest register-to-register path by number of cells"},
            {"cells", s.path.length},
            {"hops_by_type", s.path.hops_by_type},
            {"priced_period_ns", s.ltp_timing.period_ns},
            {"priced_limited_by", s.ltp_timing.limited_by}}},
          {"critical_path", critical_path_json(s.critical, s.timing)},
          {"estimated_fmax_mhz", s.timing.fmax_mhz},
          {"sensitivity_corners", corners},
          {"edif", s.edif.filename().string()}};
}

Resources sum(const Resources& a, const Resources& b) {
  Resources r;
  r.lut4 = a.lut4 + b.lut4;
  r.ff = a.ff + b.ff;
  r.mult18 = a.mult18 + b.mult18;
  r.ramb16 = a.ramb16 + b.ramb16;
  r.carry = a.carry + b.carry;
  return r;
}

// Time per step of the double reference model (semi-implicit Euler as configured by the
// scenario), the plate following the scenario's protocol. Process CPU time (std::clock),
// not wall time: the machine is shared, and other jobs must not inflate the figure.
double reference_seconds_per_step(const Scenario& scenario) {
  Simulator sim(scenario.build_model(), scenario.options);
  long long steps = 0;
  const std::clock_t start = std::clock();
  double elapsed = 0.0;
  do {
    for (int i = 0; i < 10; ++i, ++steps) {
      sim.step(scenario.plate_z(sim.model(), steps + 1));
    }
    elapsed = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  } while (elapsed < kReferenceTimingSeconds);
  return elapsed / static_cast<double>(steps);
}

void write_ucf(const fs::path& file, double period_ns) {
  std::ofstream ucf(file);
  if (!ucf) throw Error(file.string() + ": cannot write");
  ucf << "# Clock constraint for the rheo core on a Virtex-II XC2V6000 (-6), from `rheo synth`.\n"
      << "# The period is the estimate of the Yosys-based delay model (docs/synthesis.md),\n"
      << "# not a vendor timing result: run ISE's trce on the placed design to confirm it.\n"
      << "NET \"clk_i\" TNM_NET = \"clk_i\";\n"
      << "TIMESPEC \"TS_clk_i\" = PERIOD \"clk_i\" " << std::fixed << std::setprecision(2)
      << period_ns << " ns HIGH 50%;\n";
}

// The TEM design of an edge element: "tem" (the three-element edge), then "_damper" with the
// force-dependent series damper and "_arm" (one arm) or "_armsK" (K arms).
std::string tem_label(const hls::EdgeElement& e) {
  std::string label = "tem";
  if (e.series_damper) label += "_damper";
  if (e.strain_hardening) label += "_hardening";
  if (e.maxwell_arms == 1) label += "_arm";
  if (e.maxwell_arms > 1) label += "_arms" + std::to_string(e.maxwell_arms);
  return label;
}
const hls::EdgeElement* tem_element(const std::string& label) {
  for (const hls::EdgeElement& e : hls::kEdgeElements) {
    if (tem_label(e) == label) return &e;
  }
  return nullptr;
}
// The whole core built for an edge element: "core" (the baseline), "core_damper",
// "core_arms8", ... (the suffix of its TEM design).
// A core with volume elements adds "_volume", one with the tool unit "_tool" (its TEM is the
// edge element's without them).
std::string core_label(const hls::EdgeElement& e) {
  return "core" + tem_label(e).substr(3) + (e.volume_preservation ? "_volume" : "") +
         (e.tool_contact ? "_tool" : "");
}
const hls::EdgeElement* core_element(const std::string& label) {
  for (const hls::EdgeElement& e : hls::kEdgeElements) {
    if (core_label(e) == label) return &e;
  }
  return nullptr;
}
std::string design_names() {
  std::string names;
  for (const hls::EdgeElement& e : hls::kEdgeElements)
    if (!e.volume_preservation && !e.tool_contact) names += tem_label(e) + ", ";
  names += "mpm";
  for (const hls::EdgeElement& e : hls::kEdgeElements) names += ", " + core_label(e);
  return names + ", sweep";
}

// What each edge element adds to the baseline: every synthesised TEM or core design of an
// element beside the baseline design of its kind ("tem" or "core"), in LUT4, FF,
// MULT18X18, RAMB16 and clock. Printed, and returned for synth.json.
json feature_costs(const std::map<std::string, synth::SynthResult>& results) {
  json rows = json::array();
  for (const char* kind : {"tem", "core"}) {
    const auto base = results.find(kind);
    if (base == results.end()) continue;
    const Resources& b = base->second.resources;
    for (const hls::EdgeElement& e : hls::kEdgeElements) {
      if (std::string(kind) == "tem" && (e.volume_preservation || e.tool_contact))
        continue;  // another's TEM
      const std::string label = std::string(kind) == "tem" ? tem_label(e) : core_label(e);
      const auto it = results.find(label);
      if (label == kind || it == results.end()) continue;
      const Resources& r = it->second.resources;
      rows.push_back({{"design", label},
                      {"element", e.name},
                      {"baseline", kind},
                      {"lut4", r.lut4 - b.lut4},
                      {"flip_flops", r.ff - b.ff},
                      {"mult18x18", r.mult18 - b.mult18},
                      {"ramb16", r.ramb16 - b.ramb16},
                      {"fmax_mhz", it->second.timing.fmax_mhz},
                      {"baseline_fmax_mhz", base->second.timing.fmax_mhz}});
    }
  }
  if (!rows.empty()) {
    std::cout << "synth: cost of each edge element over its baseline design:\n";
    for (const json& r : rows) {
      std::cout << "  " << std::left << std::setw(20) << r["design"].get<std::string>()
                << std::right << " +" << r["lut4"].get<long long>() << " LUT4, +"
                << r["flip_flops"].get<long long>() << " FF, +" << r["mult18x18"].get<long long>()
                << " MULT18X18, +" << r["ramb16"].get<long long>() << " RAMB16, ~"
                << std::fixed << std::setprecision(0) << r["fmax_mhz"].get<double>() << " MHz ("
                << r["baseline"].get<std::string>() << ": ~"
                << r["baseline_fmax_mhz"].get<double>() << " MHz)\n";
    }
  }
  return rows;
}

// The sweep core on the chip (host/synth/sweep_performance.hpp): the synthesised build
// against the device and the board, then block5 and block15 on it. A scenario is feasible
// only when the build fits and its model fits the build; otherwise the section says why
// and its time is not offered as a result.
template <class Warn>
json sweep_core_section(const Resources& built, const synth::SweepBuild& build, double clock_mhz,
                        double fast_clock, double slow_clock, double peak_edges_per_s,
                        const Warn& warn) {
  const synth::Device device;
  const synth::ZbtPart sram;
  const synth::Package package;
  const synth::SweepFit fit = synth::sweep_fit(built, clock_mhz, build, device, sram, package);
  json section = {
      {"build", build.params()},
      {"clock_mhz_estimate", clock_mhz},
      {"clock_range_mhz", {slow_clock, fast_clock}},
      {"peak_edge_updates_per_s", peak_edges_per_s > 0 ? json(peak_edges_per_s) : json(nullptr)},
      {"resources", resources_json(built)},
      {"fits_xc2v6000", fit.fits()},
      {"problems", fit.problems},
      {"sram",
       {{"part", sram.name},
        {"devices", build.lanes * sram.devices_per_lane},
        {"latency_clocks", sram.latency_clocks},
        {"max_mhz", sram.max_mhz},
        {"source", sram.source}}},
      {"pins", {{"used", fit.pins}, {"package", package.name}, {"user_io", package.user_io},
                {"source", package.source}}},
      {"cycle_formula",
       "max over lanes of (start delay + slots) + " + std::to_string(hls::kSweepDrainCycles) +
           "; slots = max(1, cross edges) per ghost particle + max(2, own edges) per own "
           "particle (hls::sweep_cycles; the RTL counts them in status word 2)"}};
  std::cout << "sweep core (" << build.lanes << " lanes, slabs of " << build.slab_depth
            << ", ghosts of " << build.ghost_depth << "): RAMB16 " << built.ramb16 << "/"
            << device.ramb16 << ", MULT18X18 " << built.mult18 << "/" << device.mult18
            << ", slices ~" << fit.utilisation.slices << "/" << device.slices << ", pins "
            << fit.pins << "/" << package.user_io << " (" << package.name << "), "
            << build.lanes * sram.devices_per_lane << " x IDT71V3556 (" << sram.max_mhz
            << " MHz): " << (fit.fits() ? "fits" : "DOES NOT FIT") << "; clock ~" << std::setprecision(4)
            << clock_mhz << " MHz (" << slow_clock << "-" << fast_clock << ")\n";
  for (const std::string& p : fit.problems) warn("the sweep core build does not fit: " + p);
  json rows = json::array();
  for (const std::string name : {"block5", "block15"}) {
    const synth::SweepScenario s =
        synth::sweep_scenario(name, build, clock_mhz, fast_clock, slow_clock, peak_edges_per_s);
    const bool feasible = fit.fits() && s.fits_build;
    json row = {{"scenario", name}, {"particles", s.particles}, {"edges", s.edges},
                {"fits_build", s.fits_build}, {"feasible_on_one_xc2v6000", feasible}};
    if (!s.fits_build) {
      row["refused_because"] = s.refusal;
      std::cout << "perf: " << name << " on the sweep core: NOT feasible: " << s.refusal << "\n";
      warn(name + " does not fit the sweep core build: " + s.refusal);
      rows.push_back(row);
      continue;
    }
    row.update({{"lanes_used", s.lanes_used},
                {"slabs", s.lanes},
                {"cycles_per_step", s.cycles_per_step},
                {"period_cycles", s.period},
                {"estimated_us_per_step", s.us_per_step},
                {"estimated_us_one_step_alone", s.us_alone},
                {"estimated_us_per_step_range", {s.us_fast, s.us_slow}},
                {"edge_updates_per_s", s.edge_updates_per_s},
                {"fraction_of_multiplier_peak",
                 peak_edges_per_s > 0 ? json(s.fraction_of_multiplier_peak) : json(nullptr)}});
    if (name == std::string(kPaperFpgaModel))
      row["speedup_vs_paper_fpga"] = kPaperFpgaStepMs * 1e3 / s.us_per_step;
    std::cout << "perf: " << name << " on the sweep core: " << (feasible ? "" : "NOT feasible, ")
              << "L=" << s.lanes_used << " cycles=" << s.cycles_per_step;
    if (s.period > 0) std::cout << " alone, " << s.period << " apart in a command of many";
    std::cout << " -> " << std::setprecision(3) << s.us_per_step << " us/step (" << s.us_fast
              << "-" << s.us_slow << " over the delay corners";
    if (s.period > 0) std::cout << "; one step alone " << s.us_alone << " us";
    std::cout << ")";
    if (peak_edges_per_s > 0)
      std::cout << ", " << std::setprecision(3) << 100.0 * s.fraction_of_multiplier_peak
                << " % of the multiplier peak";
    if (row.contains("speedup_vs_paper_fpga"))
      std::cout << "; the paper's FPGA on the same model: " << kPaperFpgaStepMs * 1e3 << " us ("
                << std::setprecision(3) << row["speedup_vs_paper_fpga"].get<double>() << "x)";
    std::cout << "\n";
    rows.push_back(row);
  }
  section["scenarios"] = rows;
  return section;
}

void run(const Options& opt) {
  if (opt.sweep_build.size() != 4)
    throw Error("synth: --sweep-build takes four numbers: lanes, slab depth, ghost depth, window");
  synth::SweepBuild sweep_build;
  sweep_build.lanes = opt.sweep_build[0];
  sweep_build.slab_depth = opt.sweep_build[1];
  sweep_build.ghost_depth = opt.sweep_build[2];
  sweep_build.window = opt.sweep_build[3];
  output::StagedDirectory staged = stage_output(opt.output);
  const fs::path out = staged.path();
  synth::YosysSetup setup = synth::default_setup();
  if (!opt.rtl_dir.empty()) setup.rtl_dir = fs::absolute(opt.rtl_dir);
  // Figures that cannot be computed from the designs run: said in synth.json and on screen.
  json warnings = json::array();
  auto warn = [&warnings](const std::string& text) {
    warnings.push_back(text);
    std::cout << "synth: warning: " << text << "\n";
  };
  Progress progress("designs synthesised", static_cast<long long>(opt.designs.size()),
                    progress_enabled(opt.quiet));
  int designs_done = 0;

  std::map<std::string, synth::SynthResult> results;
  json designs = json::object();
  for (const std::string& label : opt.designs) {
    synth::DesignSpec spec;
    spec.label = label;
    // Source lists: rtl/sources.cmake, the same the Verilator models are built from.
    if (const hls::EdgeElement* element = tem_element(label)) {
      // The TEM of an edge element (hls/edge_element.hpp); "tem" is the baseline's.
      spec.top = "rheo_tem";
      spec.sources = synth::rtl_sources::kTemFiles;
      for (const hls::RtlParameter& p : element->rtl_parameters())
        if (p.tem) spec.params.push_back(std::string(p.name) + "=" + std::to_string(p.value));
    } else if (label == "mpm") {
      spec.top = "rheo_mpm";
      spec.sources = synth::rtl_sources::kMpmFiles;
    } else if (label == "sweep") {
      spec.top = "rheo_sweep_core";
      spec.sources = synth::rtl_sources::kSweepFiles;
      spec.params = sweep_build.params();
    } else if (const hls::EdgeElement* core = core_element(label)) {
      spec.top = opt.core_top;
      spec.sources = synth::rtl_sources::kCoreFiles;
      // Another top (--core-top) is read from the file named after it, after the core's
      // modules it may instantiate.
      const std::string top_file = opt.core_top + ".sv";
      if (std::find(spec.sources.begin(), spec.sources.end(), top_file) == spec.sources.end()) {
        spec.sources.push_back(top_file);
      }
      spec.params = {"Lanes=" + std::to_string(opt.lanes)};
      spec.params.insert(spec.params.end(), kCoreCapacityParams.begin(), kCoreCapacityParams.end());
      for (const hls::RtlParameter& p : core->rtl_parameters())
        spec.params.push_back(std::string(p.name) + "=" + std::to_string(p.value));
    } else {
      throw Error("synth: unknown design '" + label + "'; expected " + design_names());
    }
    std::cout << "synth: " << label << " (" << spec.top << ") ..." << std::flush;
    try {
      synth::SynthResult r = synth::run_synthesis(spec, setup, out);
      std::cout << " " << std::fixed << std::setprecision(1) << r.yosys_seconds << " s, "
                << r.resources.lut4 << " LUT4, " << r.resources.ff << " FF, " << r.resources.mult18
                << " MULT18X18, " << r.resources.ramb16 << " RAMB16, ~" << r.timing.fmax_mhz
                << " MHz\n";
      designs[label] = result_json(r);
      results.emplace(label, std::move(r));
    } catch (const Error& e) {
      // One design failing (e.g. RTL in progress) must not hide the others' figures.
      std::cout << " FAILED\n" << e.what() << "\n";
      designs[label] = {{"top", spec.top}, {"status", "failed"}, {"error", e.what()}};
    }
    progress.update(++designs_done);
  }
  progress.finish();
  if (results.empty()) throw Error("synth: no design synthesised; see the messages above");

  // Lanes that fit and the clock. Per lane: TEM + MPM (synthesised alone) or, when the
  // core was synthesised, its logic divided by its lanes if that is larger (it adds the
  // lane's crossbar port, force sums, LUT RAMs and control). Block RAM is not taken from
  // the synthesised core (block5 capacity, see kCoreCapacityParams) but checked per
  // scenario with the analytic estimate.
  json fit;
  double clock_mhz = 1e9;
  for (const auto& [label, r] : results) clock_mhz = std::min(clock_mhz, r.timing.fmax_mhz);
  const bool have_lane = results.count("tem") && results.count("mpm");
  if (!have_lane) {
    warn(
        "lanes that fit an XC2V6000 need both tem and mpm synthesised; not computed, the "
        "performance figures use the requested --lanes " +
        std::to_string(opt.lanes));
  }
  if (!results.count("core")) {
    warn(
        "the core was not synthesised: the clock estimate covers only the designs run and "
        "misses the core's own paths");
  }
  Resources lane;
  if (have_lane) lane = sum(results.at("tem").resources, results.at("mpm").resources);
  fit["per_lane_tem_plus_mpm"] = resources_json(lane);
  std::string lane_basis = "TEM + MPM synthesised alone (core control logic not included)";
  if (have_lane && results.count("core") && opt.lanes >= 1) {
    const Resources& core = results.at("core").resources;
    Resources core_lane;
    core_lane.lut4 = (core.lut4 + opt.lanes - 1) / opt.lanes;
    core_lane.ff = (core.ff + opt.lanes - 1) / opt.lanes;
    core_lane.mult18 = (core.mult18 + opt.lanes - 1) / opt.lanes;
    fit["per_lane_from_core"] = resources_json(core_lane);
    if (synth::estimate_slices(core_lane) > synth::estimate_slices(lane)) {
      lane.lut4 = core_lane.lut4;
      lane.ff = core_lane.ff;
      lane.mult18 = std::max(lane.mult18, core_lane.mult18);
      lane_basis = "synthesised core (" + std::to_string(opt.lanes) +
                   " lanes, block5 capacity) divided by its lanes, block RAM excluded";
    }
  }
  fit["per_lane_basis"] = lane_basis;
  const Scenario block15 = load_scenario("block15");
  const Model block15_model = block15.build_model();
  const synth::ProblemSize block15_size = synth::problem_size("block15", block15_model);
  int lanes_fit = 0;
  int last_fitting_count = 0;  // lanes_fit only grows through consecutive fitting counts
  json per_lanes = json::array();
  for (int l : hls::kLaneCounts) {
    if (!have_lane) break;
    synth::Capacity cap{block15_size.particles,
                        static_cast<int>(synth::edge_rows(block15_size, l) * l)};
    Resources total;
    total.lut4 += l * lane.lut4;
    total.ff += l * lane.ff;
    total.mult18 += l * lane.mult18;
    total.ramb16 = synth::estimate_core_ramb16(cap, l);
    const synth::Utilisation u = synth::utilisation(total);
    // Logic decides the lane count; whether a scenario's state fits the block RAM is
    // reported per scenario below (block15 does not fit on chip at any lane count).
    const bool fits = u.slices_pct <= 100.0 && u.mult18_pct <= 100.0;
    per_lanes.push_back(
        {{"lanes", l},
         {"estimated_slices", u.slices},
         {"mult18x18", total.mult18},
         {"ramb16_block15_capacity_estimate", total.ramb16},
         {"percent",
          {{"slices", u.slices_pct}, {"mult18x18", u.mult18_pct}, {"ramb16", u.ramb16_pct}}},
         {"fits", fits}});
    if (fits && lanes_fit == last_fitting_count) lanes_fit = l;
    last_fitting_count = l;
  }
  fit["candidates"] = per_lanes;
  fit["max_lanes_xc2v6000"] = have_lane ? json(lanes_fit) : json(nullptr);
  fit["lane_counts_offered"] =
      std::vector<int>(std::begin(hls::kLaneCounts), std::end(hls::kLaneCounts));
  fit["method"] =
      "L x per-lane resources (per_lane_basis) against 33,792 slices and 144 MULT18X18; "
      "RAMB16 is checked per scenario in performance.scenarios (analytic memory model, "
      "host/synth/performance_model.hpp)";
  fit["ramb16_default_capacity_estimate_1_lane"] = synth::estimate_core_ramb16({}, 1);
  if (results.count("core")) {
    fit["ramb16_analytic_at_synthesised_capacity"] =
        synth::estimate_core_ramb16(opt.core_capacity, opt.lanes);
  }

  // Performance model.
  synth::CycleModel cycle_model;
  const int lanes_used = have_lane ? std::max(1, lanes_fit) : opt.lanes;
  const int mults_per_edge = results.count("tem") ? results.at("tem").resources.mult18 : 0;
  json perf = json::object();
  perf["clock_mhz_estimate"] = clock_mhz;
  perf["lanes"] = lanes_used;
  perf["cycle_formula"] =
      "max(R, 1) + TemDrain + ceil(N/L) + MpmDrain; R = rows of the edge schedule (one edge "
      "per lane and row, end particles of a row in different banks; about ceil(E/L))";
  perf["cycle_model"] = {{"tem_drain", cycle_model.tem_drain},
                         {"mpm_drain", cycle_model.mpm_drain},
                         {"source", cycle_model.source}};
  perf["paper_2003"] = {{"fpga_xc2v6000_ms", kPaperFpgaStepMs},
                        {"pc_pentium4_1p7ghz_ms", kPaperPcStepMs},
                        {"tem", {{"slices", kPaperTemSlices}, {"mult18x18", kPaperTemMults}}},
                        {"mpm", {{"slices", kPaperMpmSlices}, {"mult18x18", kPaperMpmMults}}}};
  const double peak_edges_per_s =
      mults_per_edge > 0
          ? (synth::Device{}.mult18 / static_cast<double>(mults_per_edge)) * clock_mhz * 1e6
          : 0.0;
  perf["multipliers_per_edge"] = mults_per_edge;
  perf["peak_edge_updates_per_s"] = peak_edges_per_s > 0 ? json(peak_edges_per_s) : json(nullptr);
  if (peak_edges_per_s <= 0) {
    warn(
        "the multiplier-bound peak needs the tem synthesised (multipliers per edge); "
        "fractions of the peak are not computed");
  }
  perf["paper_comparison_rule"] =
      "a time is compared with a 2003 figure only for the model size that figure was measured "
      "on: block5 (5x5x5) with the paper's PC, block15 (15x15x16) with the paper's FPGA";
  // The clock at each corner of the sensitivity table: the slowest design at that corner.
  const std::vector<std::pair<double, double>> factors = synth::sensitivity_factors();
  std::vector<double> corner_clock(factors.size(), 1e9);
  for (const auto& [label, r] : results)
    for (std::size_t k = 0; k < factors.size() && k < r.corners.size(); ++k)
      corner_clock[k] = std::min(corner_clock[k], r.corners[k].fmax_mhz);
  const double slow_clock = *std::min_element(corner_clock.begin(), corner_clock.end());
  const double fast_clock = *std::max_element(corner_clock.begin(), corner_clock.end());
  json rows = json::array();
  std::vector<std::pair<std::string, long long>> step_cycles;
  for (const std::string name : {"block5", "block15"}) {
    const Scenario scenario = load_scenario(name);
    const Model model = scenario.build_model();
    const synth::ProblemSize size = synth::problem_size(name, model);
    const long long cycles = synth::cycles_per_step(size, lanes_used, cycle_model);
    const long long sched_rows = synth::edge_rows(size, lanes_used);
    const synth::Ramb16Breakdown ram = synth::core_ramb16_breakdown(
        {size.particles, static_cast<int>(sched_rows * lanes_used)}, lanes_used);
    const int ramb16 = ram.total();
    // A time per step is only a result for a configuration that fits the chip.
    const bool feasible = ramb16 <= synth::Device{}.ramb16;
    const double step_us = cycles / clock_mhz;
    step_cycles.emplace_back(name, cycles);
    const double edge_rate = size.edges / (step_us * 1e-6);
    json row = {{"scenario", name},
                {"particles", size.particles},
                {"edges", size.edges},
                {"edge_rows", sched_rows},
                {"edge_bubbles", sched_rows * lanes_used - size.edges},
                {"ramb16_estimate", ramb16},
                {"state_fits_on_chip", feasible},
                {"cycles_per_step", cycles},
                {"estimated_us_per_step", step_us},
                {"estimated_us_per_step_range", {cycles / fast_clock, cycles / slow_clock}},
                {"edge_updates_per_s", edge_rate},
                {"fraction_of_multiplier_peak",
                 peak_edges_per_s > 0 ? json(edge_rate / peak_edges_per_s) : json(nullptr)}};
    if (name == std::string(kPaperFpgaModel)) {
      row["speedup_vs_paper_fpga"] = kPaperFpgaStepMs * 1e3 / step_us;
    }
    if (name == std::string(kPaperPcModel)) {
      row["speedup_vs_paper_pc"] = kPaperPcStepMs * 1e3 / step_us;
    }
    const double target_us = name == std::string("block5") ? kTargetBlock5Us : kTargetBlock15Us;
    row["target_us"] = target_us;
    row["target_met"] = step_us <= target_us;
    row["peak_target_met"] = peak_edges_per_s > 0
                                 ? json(edge_rate >= kTargetPeakFraction * peak_edges_per_s)
                                 : json(nullptr);
    if (opt.time_reference) {
      const double ref = reference_seconds_per_step(scenario);
      row["reference_model_cpu_us_per_step_this_machine"] = ref * 1e6;
      row["speedup_vs_reference_model"] = ref * 1e6 / step_us;
    }
    std::cout << "perf: " << name << " E=" << size.edges << " N=" << size.particles
              << " L=" << lanes_used << " cycles=" << cycles << " -> " << std::setprecision(2)
              << step_us << " us/step (target " << target_us << " us)";
    if (row.contains("speedup_vs_paper_fpga")) {
      std::cout << "; the paper's FPGA on the same model: " << kPaperFpgaStepMs * 1e3 << " us ("
                << row["speedup_vs_paper_fpga"].get<double>() << "x)";
    }
    if (row.contains("speedup_vs_paper_pc")) {
      std::cout << "; the paper's PC on the same model: " << kPaperPcStepMs * 1e3 << " us ("
                << row["speedup_vs_paper_pc"].get<double>() << "x)";
    }
    std::cout << "\n";
    row["feasible_on_one_xc2v6000"] = feasible;
    json by_memory = json::object();
    for (const auto& [memory, n] : ram.by_memory()) by_memory[memory] = n;
    row["ramb16_by_memory"] = by_memory;
    if (!feasible) {
      row["infeasible_because"] = "the state needs about " + std::to_string(ramb16) +
                                  " RAMB16 (analytic memory model) against the chip's " +
                                  std::to_string(synth::Device{}.ramb16);
      std::cout << "perf: " << name << " is NOT feasible on one " << synth::Device{}.name
                << " at L=" << lanes_used << ": " << row["infeasible_because"].get<std::string>()
                << "; its time per step is an estimate for a design that does not fit\n"
                << "perf: " << name << " RAMB16 by memory:";
      for (const auto& [memory, n] : ram.by_memory()) std::cout << " " << memory << " " << n;
      std::cout << "\n";
      warn(name + " does not fit one " + synth::Device{}.name + " at " +
           std::to_string(lanes_used) + " lanes: " + row["infeasible_because"].get<std::string>());
    }
    rows.push_back(row);
  }
  perf["scenarios"] = rows;

  // Sensitivity: every cell delay and the net delay each at 70 %, 100 % and 130 % of the
  // model's figures (docs/synthesis.md §2): the clock and the time per step at each corner.
  json corners = json::array();
  std::cout << "sensitivity (cells x nets -> clock; us per step at L=" << lanes_used << "):\n";
  for (std::size_t k = 0; k < factors.size(); ++k) {
    json c = {{"cell_delay_factor", factors[k].first},
              {"net_delay_factor", factors[k].second},
              {"clock_mhz", corner_clock[k]}};
    std::cout << "  cells x" << std::setprecision(1) << factors[k].first << " nets x"
              << factors[k].second << ": " << std::setprecision(1) << corner_clock[k] << " MHz";
    for (const auto& [name, cycles] : step_cycles) {
      c["us_per_step"][name] = cycles / corner_clock[k];
      std::cout << ", " << name << " " << std::setprecision(2) << cycles / corner_clock[k] << " us";
    }
    std::cout << "\n";
    corners.push_back(c);
  }
  perf["sensitivity"] = {
      {"corners", corners},
      {"method",
       "static timing of each synthesised netlist again with every cell figure (T_CKO, "
       "T_DICK, T_ILO, carry, wide mux, T_MULT, T_BCKO) and the routed-net delay T_NET "
       "scaled by 0.7, 1.0 and 1.3 independently; the clock at a corner is the slowest "
       "design's"}};

  // The largest block whose state the analytic model fits in the device's block RAM at
  // the lane count used (26-neighbour lattices n x n x n, as the built-in blocks).
  json largest = nullptr;
  for (int n = 2; n <= 16; ++n) {
    const synth::ProblemSize cube = synth::lattice_problem(n, n, n);
    const long long cube_rows = synth::edge_rows(cube, lanes_used);
    const int ramb16 = synth::estimate_core_ramb16(
        {cube.particles, static_cast<int>(cube_rows * lanes_used)}, lanes_used);
    if (ramb16 > synth::Device{}.ramb16) break;
    const long long cycles = synth::cycles_per_step(cube, lanes_used, cycle_model);
    largest = {{"lattice", cube.name},      {"particles", cube.particles},
               {"edges", cube.edges},       {"ramb16_estimate", ramb16},
               {"cycles_per_step", cycles}, {"estimated_us_per_step", cycles / clock_mhz}};
  }
  perf["largest_cube_with_state_on_chip"] = largest;
  if (results.count("sweep")) {
    // The sweep core runs at its own clock: its netlist holds its TEMs and MPMs (the TEM's
    // LateCoef variant), so its static timing is the design's, at every corner.
    const synth::SynthResult& sw = results.at("sweep");
    double sw_fast = 0.0, sw_slow = 1e9;
    for (const synth::TimingCorner& c : sw.corners) {
      sw_fast = std::max(sw_fast, c.fmax_mhz);
      sw_slow = std::min(sw_slow, c.fmax_mhz);
    }
    const double sw_peak = mults_per_edge > 0 ? (synth::Device{}.mult18 / double(mults_per_edge)) *
                                                    sw.timing.fmax_mhz * 1e6
                                              : 0.0;
    perf["sweep_core"] = sweep_core_section(sw.resources, sweep_build, sw.timing.fmax_mhz,
                                            sw_fast, sw_slow, sw_peak, warn);
  } else {
    perf["sweep_core"] = nullptr;
  }
  if (!largest.is_null()) {
    std::cout << "perf: largest cube with its state on chip at L=" << lanes_used << ": "
              << largest["lattice"].get<std::string>() << " (" << largest["edges"].get<int>()
              << " edges, " << largest["ramb16_estimate"].get<int>() << " RAMB16, "
              << largest["estimated_us_per_step"].get<double>() << " us/step)\n";
  }

  json delays = json::array();
  for (const auto& d : synth::Virtex2Delays{}.all()) {
    delays.push_back({{"name", d.name}, {"ns", d.ns}, {"what", d.what}, {"source", d.source}});
  }
  const double period_ns = 1e3 / clock_mhz;
  write_ucf(out / "rheo_core.ucf", period_ns);

  json report = {{"tool", "yosys 0.23, synth_xilinx -family xc2v -flatten -ise -noiopad"},
                 {"device",
                  {{"name", "XC2V6000"},
                   {"speed_grade", -6},
                   {"slices", 33792},
                   {"mult18x18", 144},
                   {"ramb16", 144}}},
                 {"slice_formula",
                  "estimated_slices = ceil(max(LUT4, FF) / 2) (2 LUT4 + 2 FF per slice; "
                  "a lower bound)"},
                 {"lanes_requested", opt.lanes},
                 {"designs", designs},
                 {"feature_costs", feature_costs(results)},
                 {"fit", fit},
                 {"delay_model",
                  {{"figures", delays},
                   {"constraints_file", "rheo_core.ucf"},
                   {"clock_period_ns", period_ns}}},
                 {"performance", perf},
                 {"warnings", warnings}};
  std::ofstream json_out(out / "synth.json");
  json_out << output::json_text(report) << "\n";
  if (!json_out.flush()) throw Error((out / "synth.json").string() + ": write failed");
  json_out.close();
  staged.commit();
  std::cout << "synth: wrote " << (fs::path(staged.target()) / "synth.json").string() << "\n";
}

}  // namespace

void register_synth(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Synthesise the TEM, the MPM and the core for Virtex-II (Yosys synth_xilinx -family "
      "xc2v): resources, estimated clock, lanes that fit an XC2V6000, time per step; writes "
      "DIR/synth.json, EDIF netlists and a UCF clock constraint.");
  add_lanes_option(cmd, opt->lanes, "the synthesised core");
  add_output_options(cmd, opt->output);
  cmd->add_flag("--quiet,-q", opt->quiet, "no progress display on stderr");
  cmd->add_option("--designs", opt->designs,
                  "subset of " + design_names() +
                      " (tem_X and core_X: the TEM and the whole core of an edge element with "
                      "the series damper and/or Maxwell arms; their cost over tem and core is "
                      "listed)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--core-top", opt->core_top, "top module of the core")->capture_default_str();
  cmd->add_option("--sweep-build", opt->sweep_build,
                  "the sweep core's build: lanes, slab depth, ghost depth, window (default "
                  "5,1024,256,512: block15 on one XC2V6000, docs/sweep_core.md)")
      ->delimiter(',')
      ->expected(4)
      ->capture_default_str();
  cmd->add_option("--rtl-dir", opt->rtl_dir,
                  "synthesise the SystemVerilog in this folder instead of the repository's rtl/ "
                  "(same file names; a modified copy of the design)")
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("!--no-reference-timing", opt->time_reference,
                "skip timing the double reference model");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace rheo::cli
