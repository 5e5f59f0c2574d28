#include "host/cosim/cosim.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "hls/fixed_format.hpp"
#include "host/backend/backend.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/fst_signals.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::cosim {
namespace {

using driver::CoreImage;
constexpr const char* kFieldNames[6] = {"x", "y", "z", "v_x", "v_y", "v_z"};
constexpr std::size_t kMaxReportedMismatches = 10;

}  // namespace

std::string CosimMismatch::describe() const {
  std::ostringstream os;
  os.precision(17);
  os << "step " << step << ", ";
  if (edge >= 0)
    os << "edge " << edge << ", " << field;
  else if (particle < 0)
    os << (field == "plate_force" ? "plate force" : field);
  else
    os << "particle " << particle << ", field " << field;
  os << ": " << dut_name << " " << dut << " != " << golden_name << " " << golden;
  return os.str();
}

CosimResult run_cosim(const Scenario& scenario, const CosimOptions& opt) {
  if (opt.steps < 1) throw Error("cosim: steps must be at least 1");
  if (opt.compare_every < 0) throw Error("cosim: compare_every must be 0 (automatic) or more");
  CosimResult res;
  // The model every side runs: without what the core's edge element does not compute
  // (listed). The backends choose their core variant from it.
  const Model full = scenario.build_model();
  const hls::EdgeElement* element = opt.element == "auto"
                                        ? &driver::edge_element_for(full)
                                        : hls::find_edge_element(opt.element);
  if (!element) throw Error("cosim: unknown edge element '" + opt.element + "'");
  res.element = std::string(element->name);
  backend::Options bo;
  bo.lanes = opt.lanes;
  bo.trace_fst = opt.trace_fst;
  bo.input_idle_prob = opt.input_idle_prob;
  bo.output_stall_prob = opt.output_stall_prob;
  bo.seed = opt.seed;
  const std::unique_ptr<backend::Backend> dut = backend::make_backend(opt.dut, bo);
  backend::Options go;
  go.lanes = opt.lanes;
  const std::unique_ptr<backend::Backend> golden = backend::make_backend(opt.golden, go);
  // The model every side runs: the core under test's form of the hardware's model (the
  // sweep core's edges run from the lower to the higher particle), so that the golden core
  // computes the same words.
  const Model model =
      dut->prepared(driver::hardware_model(full, &res.dropped_features, *element));
  const double dt = scenario.options.dt;
  const State start = initial_state(model);
  // The image rheo_core holds, for the figures (units, schedule rows, cycle formula).
  const CoreImage image =
      driver::make_core_image(model, start, dt, opt.lanes, driver::FormatDesc{}, *element);
  if (!opt.trace_fst.empty() && opt.check_trace_size) {
    // rheo_core's cycle formula (the core a waveform is written for) before the core exists.
    const long cycles = driver::cycles_per_step_formula(image.edge_rows, image.num_particles,
                                                        opt.lanes, *element);
    const long traced = opt.trace_steps == 0 ? opt.steps : std::min(opt.trace_steps, opt.steps);
    std::ostringstream why;
    why << "waveform of " << traced << " steps x " << cycles << " clocks per step x about "
        << kTraceBytesPerClock << " bytes per clock";
    opt.check_trace_size(double(traced) * double(cycles) * kTraceBytesPerClock, why.str());
  }
  dut->load(model, start, scenario.options);
  golden->load(model, start, scenario.options);
  res.cycles_per_step_formula = dut->cycles_per_step_formula().value_or(
      driver::cycles_per_step_formula(image.edge_rows, image.num_particles, opt.lanes, *element));
  res.dut_name = opt.dut;
  res.golden_name = opt.golden;
  res.particles = image.num_particles;
  res.edges = image.num_edges;
  res.edge_rows = image.edge_rows;
  res.lanes = opt.lanes;
  res.length_unit_m = image.units.length_m;
  res.force_unit_N = image.units.force_N;
  res.dt_s = dt;
  res.dut_description = dut->describe();
  if (res.dut_description.contains("lanes")) res.lanes = res.dut_description["lanes"].get<int>();
  const std::optional<backend::CoreClock> clock_start = dut->clock();

  std::unique_ptr<backend::Backend> ref;
  if (opt.run_reference) {
    ref = backend::make_backend("ref");
    ref->load(model, start, scenario.options);
  }
  const double size = image.extent_m;
  double sq_sum = 0.0;
  long sq_count = 0;
  const int np = image.num_particles;
  auto mismatch = [&](long step, int particle, const std::string& field, double d, double g,
                      int edge = -1) {
    ++res.mismatches;
    if (res.first.size() < kMaxReportedMismatches)
      res.first.push_back({step, particle, field, d, g, opt.dut, opt.golden, edge});
  };

  const std::size_t tools = model.tools.size();
  long step = 0;
  const bool automatic = opt.compare_every == 0;
  // Simulated cycles so far (automatic K; 0 with a core that has no clock).
  auto sim_cycles_now = [&]() -> std::uint64_t {
    const std::optional<backend::CoreClock> c = dut->clock();
    return c ? c->sim_cycles : 0;
  };
  res.compare_every = automatic ? 1 : opt.compare_every;
  long expected_cycles = 0;  // by the formula, over the run commands below
  while (step < opt.steps) {
    const long batch = std::min<long>(res.compare_every, opt.steps - step);
    const std::uint64_t before_run = automatic ? sim_cycles_now() : 0;
    const bool traced = !opt.trace_fst.empty() && (opt.trace_steps == 0 || step < opt.trace_steps);
    dut->set_tracing(traced);
    std::vector<double> plate_z(batch);
    std::vector<ToolPose> poses;
    for (long b = 0; b < batch; ++b) {
      plate_z[b] = scenario.plate_z(model, step + b + 1);
      if (tools > 0) {
        const std::vector<ToolPose> p = scenario.tool_poses(step + b + 1);
        poses.insert(poses.end(), p.begin(), p.end());
      }
    }
    // A model with tools: their poses each step, and their reactions compared as well.
    std::vector<ToolReaction> r_golden, r_dut, r_ref;
    auto run = [&](backend::Backend& b, std::vector<ToolReaction>& r) {
      return tools > 0 ? b.run_tools(plate_z, poses, r) : b.run(plate_z);
    };
    const std::vector<double> f_golden = run(*golden, r_golden);
    const std::uint64_t batch_start = dut->trace_time();
    const std::vector<double> f_dut = run(*dut, r_dut);
    expected_cycles +=
        dut->command_cycles_formula(batch).value_or(batch * res.cycles_per_step_formula);
    if (traced) res.traced.push_back({step + 1, batch, batch_start, dut->trace_time()});
    const std::vector<double> f_ref = ref ? run(*ref, r_ref) : std::vector<double>{};
    for (long b = 0; b < batch; ++b) {
      if (f_dut[b] != f_golden[b]) mismatch(step + b + 1, -1, "plate_force", f_dut[b], f_golden[b]);
      res.force_fixed_N.push_back(f_golden[b]);
      if (ref) res.force_ref_N.push_back(f_ref[b]);
      for (std::size_t t = 0; t < tools; ++t) {
        const std::size_t k = std::size_t(b) * tools + t;
        for (int a = 0; a < 3; ++a) {
          if (r_dut[k].force[a] != r_golden[k].force[a]) {
            mismatch(step + b + 1, -1, "tool " + std::to_string(t) + " force " + "xyz"[a],
                     r_dut[k].force[a], r_golden[k].force[a]);
          }
        }
        res.tool_force_fixed_N.push_back(r_golden[k].force);
        if (ref) res.tool_force_ref_N.push_back(r_ref[k].force);
      }
    }
    step += batch;
    // Every particle position and velocity of the core under test against the golden core.
    const std::uint64_t after_run = automatic ? sim_cycles_now() : 0;
    const State s_dut = dut->particle_state();
    const std::uint64_t after_read = automatic ? sim_cycles_now() : 0;
    if (automatic && step == batch) {
      // The first comparison sets K from what one step and one read-back cost.
      if (after_run > before_run) {
        res.step_cycles = (after_run - before_run) / std::uint64_t(batch);
        res.readback_cycles = after_read - after_run;
        res.compare_every = static_cast<int>(std::clamp<std::uint64_t>(
            (res.readback_cycles + res.step_cycles - 1) / res.step_cycles, 1, 1u << 20));
      }
    }
    const State s_golden = golden->particle_state();
    for (int i = 0; i < np; ++i) {
      for (int f = 0; f < 6; ++f) {
        const double d = f < 3 ? s_dut.x[i][f] : s_dut.v[i][f - 3];
        const double g = f < 3 ? s_golden.x[i][f] : s_golden.v[i][f - 3];
        if (d != g) mismatch(step, i, kFieldNames[f], d, g);
      }
    }
    if (ref) {
      const State& rs = *ref->resident_state();
      double step_max = 0.0;
      for (int i = 0; i < np; ++i) {
        const double e = (s_golden.x[i] - rs.x[i]).norm() / size;
        step_max = std::max(step_max, e);
        sq_sum += e * e;
        ++sq_count;
      }
      res.max_pos_err_rel = std::max(res.max_pos_err_rel, step_max);
      res.final_max_pos_err_rel = step_max;
    }
    if (opt.progress) opt.progress(step);
    if (res.mismatches > 0) break;
  }
  res.steps = step;
  if (res.mismatches == 0) {
    // The whole state once, after the last step: every particle word again, and the Voigt
    // lengths and the arms' extensions, which the read-backs above leave out to be fast.
    const State f_dut = dut->state(), f_golden = golden->state();
    auto compare_edges = [&](const std::vector<double>& d, const std::vector<double>& g,
                             std::size_t per_edge, const std::string& field) {
      if (d.empty() || g.empty()) return;  // a part one side does not compute (the sweep core's arms)
      if (d.size() != g.size()) {
        throw Error("cosim: " + res.dut_name + " and " + res.golden_name + " return " +
                    std::to_string(d.size()) + " and " + std::to_string(g.size()) + " " +
                    field + " values");
      }
      for (std::size_t k = 0; k < d.size(); ++k) {
        if (d[k] != g[k]) {
          mismatch(step, -1, per_edge > 1 ? field + " " + std::to_string(k % per_edge) : field,
                   d[k], g[k], int(k / per_edge));
        }
      }
      res.final_state_words += long(d.size());
    };
    for (int i = 0; i < np; ++i) {
      for (int f = 0; f < 6; ++f) {
        const double d = f < 3 ? f_dut.x[i][f] : f_dut.v[i][f - 3];
        const double g = f < 3 ? f_golden.x[i][f] : f_golden.v[i][f - 3];
        if (d != g) mismatch(step, i, kFieldNames[f], d, g);
      }
    }
    res.final_state_words += 6L * np;
    compare_edges(f_dut.d, f_golden.d, 1, "Voigt length d");
    compare_edges(f_dut.m, f_golden.m, 1, "arm extension");
    const std::size_t stride =
        f_golden.d.empty() ? 1 : std::max<std::size_t>(1, f_golden.spectrum.size() / f_golden.d.size());
    compare_edges(f_dut.spectrum, f_golden.spectrum, stride, "spectrum arm");
  }
  res.cycles_per_step_expected = double(expected_cycles) / double(std::max<long>(step, 1));
  if (sq_count > 0) res.rms_pos_err_rel = std::sqrt(sq_sum / double(sq_count));
  if (ref) {
    double fmax = 0.0, emax = 0.0;
    for (std::size_t i = 0; i < res.force_ref_N.size(); ++i) {
      fmax = std::max(fmax, std::fabs(res.force_ref_N[i]));
      emax = std::max(emax, std::fabs(res.force_fixed_N[i] - res.force_ref_N[i]));
    }
    res.max_force_ref_N = fmax;
    res.max_force_err_rel = fmax > 0.0 ? emax / fmax : emax;
    double tmax = 0.0, temax = 0.0;
    std::vector<double> terr(res.tool_force_ref_N.size());
    for (std::size_t i = 0; i < res.tool_force_ref_N.size(); ++i) {
      tmax = std::max(tmax, res.tool_force_ref_N[i].norm());
      terr[i] = (res.tool_force_fixed_N[i] - res.tool_force_ref_N[i]).norm();
      if (terr[i] > temax) {
        temax = terr[i];
        res.max_tool_force_err_step = long(i / std::max<std::size_t>(tools, 1)) + 1;
      }
    }
    const double scale = tmax > 0.0 ? tmax : 1.0;
    res.max_tool_force_ref_N = tmax;
    res.max_tool_force_err_rel = temax / scale;
    if (!terr.empty()) {
      auto mid = terr.begin() + std::ptrdiff_t(terr.size() / 2);
      std::nth_element(terr.begin(), mid, terr.end());
      res.median_tool_force_err_rel = *mid / scale;
    }
  }
  if (const std::optional<backend::CoreClock> clock_end = dut->clock(); clock_end && clock_start) {
    res.cycles_per_step_measured =
        double(std::uint32_t(clock_end->core_cycles - clock_start->core_cycles)) /
        double(std::max<long>(step, 1));
    res.sim_cycles = clock_end->sim_cycles;
    res.sim_cycles_per_s =
        clock_end->sim_wall_s > 0 ? double(clock_end->sim_cycles) / clock_end->sim_wall_s : 0.0;
  }
  return res;
}

std::string write_trace_gtkw(const CosimResult& r, const CosimOptions& opt,
                             const std::string& filter_command, const std::string& final_fst) {
  namespace fs = std::filesystem;
  if (opt.trace_fst.empty()) throw Error("gtkw: the run wrote no waveform");
  if (r.traced.empty()) throw Error("gtkw: no step of the run is in " + opt.trace_fst);
  const driver::FstContents fst = driver::read_fst_signals(opt.trace_fst);
  if (r.traced.front().start_time < fst.start_time || r.traced.front().end_time > fst.end_time)
    throw Error("gtkw: step " + std::to_string(r.traced.front().first_step) +
                " lies outside the times of " + opt.trace_fst);
  driver::GtkwOptions g;
  g.lanes = r.lanes;
  if (r.dut_description.value("core", "") == "sweep") {
    // The sweep core sits in its testbench with the SRAM models (rtl/rheo_sweep_tb.sv).
    g.sweep = true;
    g.core_scope = "rheo_core.rheo_sweep_tb.rheo_core";
  }
  const hls::EdgeElement* element = hls::find_edge_element(r.element);
  g.maxwell_arms = element ? element->maxwell_arms : 0;
  // The RTL implements the hardware format (rtl/rheo_consts_pkg.sv is generated from it).
  g.format = driver::FormatDesc::of<hls::HardwareFormat>();
  g.units = driver::Units{r.length_unit_m, r.force_unit_N, r.dt_s};
  g.filter_command = filter_command;
  g.steps = r.traced;
  g.dump_file = fs::absolute(final_fst.empty() ? opt.trace_fst : final_fst).string();
  const std::string text = driver::make_gtkw(fst.signals, g);
  const std::string path = fs::path(opt.trace_fst).replace_extension(".gtkw").string();
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw Error("cannot write " + path);
  return path;
}

}  // namespace rheo::cosim
