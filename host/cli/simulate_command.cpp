// `rheo simulate`: runs a scenario on the double-precision reference model (or, with
// --backend, on the bit-true model, the RTL core or a cosim-server) and writes the
// plate force history (docs/data-format.md CSV), a VTK time series and a PNG plot into --out.
// Everything is staged in a temporary directory and moved into place only after the
// whole run succeeded, so a failure (bad input, unstable dt, non-finite state, Ctrl-C)
// never leaves files that look like results.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "hls/fixed_format.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/driver/link/backend_run.hpp"
#include "host/output/force_csv.hpp"
#include "host/output/gnuplot_plot.hpp"
#include "host/output/run_summary.hpp"
#include "host/output/staged_directory.hpp"
#include "host/output/vtk_series.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct SimulateArgs {
  std::string scenario;
  OutputOptions output;
  std::optional<double> duration_s;
  std::optional<long long> steps;
  bool quiet = false;
  bool no_plot = false;
  std::string backend = "ref";  // ref | bittrue | rtl | remote:PATH
  int lanes = hls::kDefaultLanes;
};

// Ctrl-C during a long run: finish the current step, then fail like any other error so
// that the staged output is removed.
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) { g_interrupted = 1; }

class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted = 0;
    old_int_ = std::signal(SIGINT, on_interrupt);
    old_term_ = std::signal(SIGTERM, on_interrupt);
  }
  ~InterruptGuard() {
    std::signal(SIGINT, old_int_);
    std::signal(SIGTERM, old_term_);
  }

 private:
  void (*old_int_)(int);
  void (*old_term_)(int);
};

// The particles whose downward displacement is "the top surface at its centre" (§7):
// the top layer's particles closest to the centre of the top face (one in an odd grid,
// two or four in an even one; the mean is reported).
std::vector<int> top_centre_particles(const Model& model) {
  double top = -1e300;
  for (const Vec3& p : model.x0) top = std::max(top, p.z());
  const double tolerance = 1e-9 * std::max(model.size, 1e-12);
  double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300;
  std::vector<int> layer;
  for (int i = 0; i < model.num_particles(); ++i) {
    const Vec3& p = model.x0[i];
    if (p.z() < top - tolerance) continue;
    layer.push_back(i);
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
    y_min = std::min(y_min, p.y());
    y_max = std::max(y_max, p.y());
  }
  const double cx = 0.5 * (x_min + x_max), cy = 0.5 * (y_min + y_max);
  auto distance = [&](int i) { return std::hypot(model.x0[i].x() - cx, model.x0[i].y() - cy); };
  double best = 1e300;
  for (int i : layer) best = std::min(best, distance(i));
  std::vector<int> centre;
  for (int i : layer) {
    if (distance(i) <= best + tolerance) centre.push_back(i);
  }
  return centre;
}

double surface_displacement_mm(const Model& model, const State& state,
                               const std::vector<int>& particles) {
  double sum = 0.0;
  for (int i : particles) sum += model.x0[i].z() - state.x[i].z();
  return 1e3 * sum / particles.size();
}

std::string format(double x, const char* fmt = "%.6g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, x);
  return buf;
}

const char* integrator_name(Integrator i) {
  return i == Integrator::kRK4 ? "rk4" : "semi_implicit_euler";
}

// Decimals of time_s that keep successive rows distinct and readable.
int time_decimals(double row_interval_s) {
  return std::clamp(static_cast<int>(std::ceil(-std::log10(row_interval_s) - 1e-9)) + 1, 3, 9);
}

void run_simulate(const SimulateArgs& args) {
  const Scenario scenario = load_scenario(args.scenario);
  const Model model = scenario.build_model();
  const double dt = scenario.options.dt;
  long long steps = scenario.default_steps();
  if (args.steps) steps = *args.steps;
  if (args.duration_s) steps = steps_for_duration(*args.duration_s, dt, "--duration");

  // The simulator refuses an unstable dt before anything is created on disk.
  Simulator sim(model, scenario.options);
  output::StagedDirectory out(args.output.out, args.output.force);
  const std::string dir = out.path();

  const double run_s = steps * dt;
  const double csv_interval =
      scenario.output.csv_interval_s > 0.0 ? scenario.output.csv_interval_s : dt;
  const double vtk_interval =
      scenario.output.vtk_interval_s > 0.0 ? scenario.output.vtk_interval_s : run_s / 100.0;
  const std::vector<int> centre = top_centre_particles(model);

  const output::Specimen specimen{scenario.block.sz * 1e3, scenario.block.sx * 1e3,
                                  scenario.block.sy * 1e3};
  const EdgeMaterial& mat = scenario.block.material;
  const std::vector<std::pair<std::string, std::string>> extra = {
      {"source", args.backend == "ref" ? "rheo simulate (double-precision reference model)"
                                       : "rheo simulate (fixed-point core: bittrue, rtl and "
                                         "remote give the same numbers)"},
      {"scenario", scenario.name},
      {"integrator", integrator_name(scenario.options.integrator)},
      {"dt_s", format(dt)},
      {"mass_scale", format(scenario.block.mass_scale)},
      {"material", "three_element k1=" + format(mat.k1) + " Pa, c1=" + format(mat.c1) +
                       " Pa s, c2=" + format(mat.c2) + " Pa s"},
      {"particles", std::to_string(model.num_particles())},
      {"edges", std::to_string(model.num_edges())},
  };
  output::ForceCsvWriter csv(dir + "/force.csv", specimen, extra, time_decimals(csv_interval));
  // Fixed-point backends read back positions and velocities, not the edges' Voigt lengths:
  // their frames leave out edge tension and stress instead of writing zeros.
  output::FrameContent vtk_content;
  if (args.backend != "ref") {
    vtk_content.edge_states = false;
    vtk_content.absent_reason =
        "the fixed-point core's edge Voigt lengths are not read back, so edge tensions cannot be "
        "computed on the host";
  }
  output::VtkSeriesWriter vtk(model, dir, vtk_content);
  auto plate_frame = [&](double plate_mm, double force_N) {
    return output::PlateFrame{model.height - plate_mm * 1e-3, plate_mm * 1e-3, force_N};
  };

  // The first row and frame: the object at rest before the plate moves.
  csv.write_row(0.0, scenario.protocol.displacement_mm(0.0), 0.0,
                surface_displacement_mm(model, sim.state(), centre));
  vtk.write_frame(sim.state(), plate_frame(scenario.protocol.displacement_mm(0.0), 0.0));

  InterruptGuard interrupt_guard;
  Progress progress("step", steps, progress_enabled(args.quiet));
  // Row and frame times are multiples of their intervals; comparing with a small slack
  // keeps rounding in i * dt from skipping one.
  const double slack = 1e-9 * dt;
  double next_csv = csv_interval, next_vtk = vtk_interval;
  output::RunSummary figures(scenario.protocol);
  figures.add(0.0, 0.0, 0.0);
  const auto start = Clock::now();
  // One step's result, whatever computed it: the CSV row, the VTK frame and the progress.
  auto record = [&](long long i, double plate_mm, double force_N, const State* state) {
    const double t = i * dt;
    if (!std::isfinite(force_N)) {
      throw Error("non-finite plate force at step " + std::to_string(i) + " (t = " + format(t) +
                  " s): the run is numerically unstable");
    }
    figures.add(t, force_N,
                state ? surface_displacement_mm(model, *state, centre)
                      : std::numeric_limits<double>::quiet_NaN());
    if (t >= next_csv - slack || i == steps) {
      // Fixed-point backends return positions only every few steps; surface_mm stays
      // empty (docs/data-format.md) on the rows in between.
      csv.write_row(t, plate_mm, force_N,
                    state ? surface_displacement_mm(model, *state, centre)
                          : std::numeric_limits<double>::quiet_NaN());
      while (next_csv <= t + slack) next_csv += csv_interval;
    }
    if (state && (t >= next_vtk - slack || i == steps)) {
      vtk.write_frame(*state, plate_frame(plate_mm, force_N));
      while (next_vtk <= t + slack) next_vtk += vtk_interval;
    }
    if (g_interrupted) throw Error("interrupted at step " + std::to_string(i) + "; no output kept");
    progress.update(i);
  };

  if (args.backend == "ref") {
    for (long long i = 1; i <= steps; ++i) {
      const double plate_mm = scenario.plate_mm(i);
      const StepReport report = sim.step(scenario.plate_z(model, i));
      record(i, plate_mm, report.plate_force_N, &sim.state());
    }
  } else {
    // Fixed-point backends stream the plate in and the force out every step; positions and
    // velocities come back every vtk-frame interval.
    link::BackendRunOptions options;
    options.backend = args.backend;
    options.lanes = args.lanes;
    options.steps = static_cast<std::uint64_t>(steps);
    options.state_every = static_cast<std::uint64_t>(std::max(1.0, std::round(vtk_interval / dt)));
    long long pending_step = 0;
    double pending_plate = 0.0, pending_force = 0.0;
    State frame = initial_state(model);
    // A step's force arrives before (or with) its positions: hold the last step back until
    // the positions of that step, if any, are known.
    auto flush = [&](const State* state) {
      if (pending_step > 0) record(pending_step, pending_plate, pending_force, state);
      pending_step = 0;
    };
    link::BackendRunCallbacks callbacks;
    callbacks.step = [&](const link::BackendStep& s) {
      flush(nullptr);
      pending_step = static_cast<long long>(s.step);
      pending_plate = s.plate_mm;
      pending_force = s.force_N;
    };
    callbacks.state = [&](std::uint64_t done, const std::vector<Vec3>& positions,
                          const std::vector<Vec3>& velocities) {
      frame.x = positions;
      frame.v = velocities;
      frame.t = static_cast<double>(done) * dt;
      if (pending_step == static_cast<long long>(done)) {
        flush(&frame);
      }
    };
    const link::BackendRunSummary summary =
        link::run_scenario_on_backend(scenario, options, callbacks);
    flush(nullptr);
    for (const std::string& f : summary.dropped_features) {
      std::cerr << "rheo simulate: note: backend " << summary.device_name << " leaves out " << f
                << "\n";
    }
  }
  progress.finish();
  const double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  csv.close();
  vtk.close();

  if (!args.no_plot) {
    output::plot_force_csv({dir, "force.csv", csv.header_lines(), "plot.gp", "plot.png",
                            "rheo simulate: " + scenario.name});
  }
  out.commit();

  const std::string target = out.target();
  std::cout << "rheo simulate: " << scenario.name << ", " << model.num_particles() << " particles, "
            << model.num_edges() << " edges, " << steps << " steps of " << format(dt) << " s ("
            << format(run_s) << " s simulated) in " << format(wall_s, "%.2f") << " s ("
            << format(steps / std::max(wall_s, 1e-9), "%.0f") << " steps/s)\n";
  for (const std::string& line : figures.lines()) std::cout << "  " << line << "\n";
  std::cout << "  force CSV:  " << target << "/force.csv\n"
            << "  VTK series: " << target << "/mesh.pvd (" << vtk.frames() << " frames in "
            << target << "/vtk/, open the .pvd in ParaView)\n";
  if (const std::vector<std::string> absent = vtk.absent_arrays(); !absent.empty()) {
    std::cout << "  VTK note:   no";
    for (std::size_t i = 0; i < absent.size(); ++i) std::cout << (i ? ", " : " ") << absent[i];
    std::cout << " in the frames: "
              << (vtk_content.absent_reason.empty() ? "the 2-D model has no depth (top area)"
                                                    : vtk_content.absent_reason)
              << "\n";
  }
  if (!args.no_plot) {
    std::cout << "  plot:       " << target << "/plot.png (script " << target << "/plot.gp)\n";
  }
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Run a scenario (mesh, material, plate protocol) on the double-precision reference model "
      "(or, with --backend, on the bit-true model, the RTL core or a cosim-server) and write into "
      "--out: force.csv (plate force history, docs/data-format.md columns "
      "time_s,plate_mm,force_N,surface_mm), mesh.pvd + edges.pvd + vtk/*.vtu (VTK time series for "
      "ParaView: the object's cells with displacement, velocity, strain and stress, the plate, "
      "the edge lattice with edge tension; docs/output.md) and plot.png (force and "
      "displacements against time, drawn by gnuplot). Results are staged in a temporary "
      "directory and appear in --out only when the whole run succeeded.");
  cmd->add_option("--scenario", args->scenario,
                  "built-in scenario name (see `rheo scenarios`) or path to a JSON scenario file")
      ->required();
  add_output_options(cmd, args->output);
  auto* duration = cmd->add_option("--duration", args->duration_s,
                                   "simulated time [s] (default: the scenario's duration)");
  duration->check(CLI::PositiveNumber);
  auto* steps = add_steps_option(cmd, args->steps, "number of time steps (default: duration / dt)");
  duration->excludes(steps);
  cmd->add_flag("--quiet,-q", args->quiet, "no progress display on stderr");
  cmd->add_flag("--no-plot", args->no_plot, "do not draw plot.png (no gnuplot needed)");
  cmd->add_option("--backend", args->backend,
                  "model that computes the run: ref (double reference, default), bittrue "
                  "(fixed-point HLS-style model), rtl (Verilator core in process) or remote:PATH "
                  "(cosim-server on a Unix socket); bittrue, rtl and remote give identical numbers")
      ->capture_default_str();
  add_lanes_option(cmd, args->lanes, "an in-process rtl or bittrue core");
  cmd->callback([args]() { run_simulate(*args); });
}

}  // namespace rheo::cli
