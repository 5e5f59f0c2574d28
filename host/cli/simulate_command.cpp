// `rheo simulate`: runs a scenario on the double-precision reference model (or, with
// --backend, on the bit-true model, the RTL core or a cosim-server) and writes the
// plate force history (docs/data-format.md CSV), a VTK time series and a PNG plot into --out.
// Everything is staged in a temporary directory and moved into place only after the
// whole run succeeded, so a failure (bad input, unstable dt, non-finite state, Ctrl-C)
// never leaves files that look like results.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
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
#include "host/backend/backend.hpp"
#include "host/output/force_csv.hpp"
#include "host/output/gnuplot_plot.hpp"
#include "host/output/run_summary.hpp"
#include "host/output/staged_directory.hpp"
#include "host/output/vtk_series.hpp"
#include "sim/element_watch.hpp"
#include "sim/error.hpp"
#include "sim/hold_watch.hpp"
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
  std::string backend = "ref";  // a backend::make_backend spec
  int lanes = hls::kDefaultLanes;
  bool allow_dropped = false;  // run on a backend that leaves out features of the scenario
  CpuArgs cpu;                 // ref: fast or scalar CPU path
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

// Longest run of steps handed to a backend at once: bounds the memory of a batch and the
// delay of the progress display and of Ctrl-C.
constexpr long long kMaxBatchSteps = 4096;

// Simulated time between the hold watch's looks at the state (sim/hold_watch.hpp), on a
// backend that keeps no state in host memory: a buckling mesh grows over seconds.
constexpr double kWatchInterval_s = 1.0;

// First step whose time reaches `t_s` (with slack against rounding), at least `after` + 1.
long long first_step_at(double t_s, double dt, long long after) {
  const double slack = 1e-9 * dt;
  const double steps = std::ceil((t_s - slack) / dt);
  if (!(steps < 9e18)) return std::numeric_limits<long long>::max();
  return std::max(after + 1, static_cast<long long>(steps));
}

void run_simulate(const SimulateArgs& args) {
  const Scenario scenario = load_scenario(args.scenario);
  const Model model = scenario.build_model();
  const double dt = scenario.options.dt;
  // The scenario's duration only when neither --steps nor --duration says otherwise.
  long long steps = args.steps || args.duration_s ? 0 : scenario.default_steps();
  if (args.steps) steps = *args.steps;
  if (args.duration_s) steps = steps_for_duration(*args.duration_s, dt, "--duration");

  // Every backend refuses an unstable dt or a model it cannot hold before anything is
  // created on disk.
  backend::Options backend_options;
  backend_options.lanes = args.lanes;
  backend_options.cpu = cpu_options(args.cpu);
  const std::unique_ptr<backend::Backend> engine =
      backend::make_backend(args.backend, backend_options);
  const State start_state = initial_state(model);
  engine->load(model, start_state, scenario.options);
  // A backend that cannot compute part of the scenario would simulate another object: that
  // is refused unless asked for, and then said.
  const std::vector<std::string> dropped = engine->dropped_features();
  if (!dropped.empty() && !args.allow_dropped) {
    std::string list;
    for (const std::string& f : dropped) list += (list.empty() ? "" : "; ") + f;
    throw Error("backend " + engine->name() + " does not compute part of scenario " +
                scenario.name + ": " + list +
                ". Run it on --backend ref, or pass --allow-dropped to simulate the object "
                "without them");
  }
  for (const std::string& f : dropped) {
    std::cerr << "rheo simulate: note: backend " << engine->name() << " leaves out " << f << "\n";
  }
  const nlohmann::json engine_info = engine->describe();
  if (engine_info.contains("cpu_note") && args.cpu.path == "fast") {
    std::cerr << "rheo simulate: note: " << engine_info["cpu_note"].get<std::string>() << "\n";
  }
  output::StagedDirectory out = stage_output(args.output);
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
      {"source", "rheo simulate (" + engine->arithmetic() + ")"},
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
  output::FrameContent content;
  content.plate = scenario.plate;
  output::VtkSeriesWriter vtk(model, dir, content);
  // Tools: their poses per step from the scenario, their reactions into tools.csv and the
  // VTK frames.
  const std::size_t tools = model.tools.size();
  std::unique_ptr<std::ofstream> tool_csv;
  std::vector<ToolReaction> reactions, last_reactions(tools);
  std::vector<std::pair<double, double>> tool_peak(tools, {0.0, 0.0});  // |F| [N], t [s]
  auto tool_frames = [&](long long step) {
    std::vector<output::ToolFrame> frames;
    const std::vector<ToolPose> poses = scenario.tool_poses(step);
    for (std::size_t k = 0; k < tools; ++k) {
      frames.push_back({model.tools[k].name, tool_surface(model.tools[k], poses[k], model.size),
                        last_reactions[k]});
    }
    return frames;
  };
  if (tools > 0) {
    tool_csv = std::make_unique<std::ofstream>(dir + "/tools.csv");
    *tool_csv << "# rheo-tools: 1\n# scenario: " << scenario.name
              << "\n# reaction of the objects on each tool (force [N], torque about the tool's "
                 "position [N m]), pose (position [m], q: roller angle [rad] or gripper opening "
                 "[m]) and particles in contact, every step\ntime_s";
    for (const Tool& tool : model.tools) {
      for (const char* c : {"fx_N", "fy_N", "fz_N", "tx_N_m", "ty_N_m", "tz_N_m", "x_m", "y_m",
                            "z_m", "q", "contacts"}) {
        *tool_csv << "," << tool.name << "_" << c;
      }
    }
    *tool_csv << "\n";
  }
  // Several objects: each one's centre of mass and mean velocity, on the CSV rows whose
  // state the backend gives.
  const int objects = static_cast<int>(model.object_names.size());
  std::unique_ptr<std::ofstream> object_csv;
  if (objects > 1) {
    object_csv = std::make_unique<std::ofstream>(dir + "/objects.csv");
    *object_csv << "# rheo-objects: 1\n# scenario: " << scenario.name
                << "\n# centre of mass [m] and its velocity [m/s] of each object\ntime_s";
    for (const std::string& name : model.object_names) {
      for (const char* c : {"x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s"}) {
        *object_csv << "," << name << "_" << c;
      }
    }
    *object_csv << "\n";
  }
  auto write_object_row = [&](double t, const State& state) {
    if (!object_csv) return;
    std::vector<Vec3> x(objects, Vec3::Zero()), v(objects, Vec3::Zero());
    std::vector<double> m(objects, 0.0);
    for (int i = 0; i < model.num_particles(); ++i) {
      const int k = model.object[i];
      x[k] += model.mass[i] * state.x[i];
      v[k] += model.mass[i] * state.v[i];
      m[k] += model.mass[i];
    }
    *object_csv << format(t, "%.9g");
    for (int k = 0; k < objects; ++k) {
      for (int c = 0; c < 3; ++c) *object_csv << "," << format(x[k][c] / m[k], "%.9g");
      for (int c = 0; c < 3; ++c) *object_csv << "," << format(v[k][c] / m[k], "%.9g");
    }
    *object_csv << "\n";
  };
  auto write_tool_row = [&](long long step) {
    if (!tool_csv) return;
    const std::vector<ToolPose> poses = scenario.tool_poses(step);
    *tool_csv << format(step * dt, "%.9g");
    for (std::size_t k = 0; k < tools; ++k) {
      const ToolReaction& r = last_reactions[k];
      for (double v : {r.force.x(), r.force.y(), r.force.z(), r.torque.x(), r.torque.y(),
                       r.torque.z(), poses[k].position.x(), poses[k].position.y(),
                       poses[k].position.z(), poses[k].q}) {
        *tool_csv << "," << format(v, "%.9g");
      }
      *tool_csv << "," << r.contacts;
    }
    *tool_csv << "\n";
  };
  auto plate_frame = [&](double plate_mm, double force_N) {
    return output::PlateFrame{model.height - plate_mm * 1e-3, plate_mm * 1e-3, force_N};
  };

  // The first row and frame: the object at rest before the plate moves.
  csv.write_row(0.0, scenario.protocol.displacement_mm(0.0), 0.0,
                surface_displacement_mm(model, start_state, centre));
  vtk.write_frame(start_state, plate_frame(scenario.protocol.displacement_mm(0.0), 0.0),
                  tool_frames(0));
  write_tool_row(0);
  write_object_row(0.0, start_state);

  {
    // The output budget, from what the first row and frame took: every frame of the series
    // is as large as the first, every row about as long.
    namespace fs = std::filesystem;
    std::error_code ec;
    double frame_bytes = 0.0;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(dir) / "vtk", ec))
      if (e.is_regular_file(ec)) frame_bytes += static_cast<double>(e.file_size(ec));
    // At most one frame and one row per step, and one at the start.
    const double most = static_cast<double>(steps) + 1.0;
    const double frames = std::min(std::floor(run_s / vtk_interval + 1e-9) + 1.0, most);
    const double rows = std::min(std::floor(run_s / csv_interval + 1e-9) + 1.0, most);
    const double row_bytes = 60.0 + 170.0 * static_cast<double>(tools) +
                             (objects > 1 ? 100.0 * objects : 0.0);
    const double vtk_bytes = frames * frame_bytes, csv_bytes = rows * row_bytes;
    char breakdown[300];
    std::snprintf(breakdown, sizeof breakdown,
                  "%.0f VTK frames of %.3g MB, one every %g s (output.vtk_interval_s, at most "
                  "one per step), and %.0f CSV rows of about %.0f bytes, one every %g s "
                  "(output.csv_interval_s)",
                  frames, frame_bytes / 1e6, vtk_interval, rows, row_bytes, csv_interval);
    check_output_budget(args.output, vtk_bytes + csv_bytes, breakdown);
  }

  Progress progress("step", steps, progress_enabled(args.quiet));
  // Row and frame times are multiples of their intervals; comparing with a small slack
  // keeps rounding in i * dt from skipping one.
  const double slack = 1e-9 * dt;
  double next_csv = csv_interval, next_vtk = vtk_interval;
  // The hold watch looks at the state at least once a simulated second (kWatchInterval_s).
  const double watch_interval = std::min(kWatchInterval_s, vtk_interval);
  double next_watch = watch_interval;
  output::RunSummary figures(scenario.protocol);
  figures.add(0.0, 0.0, 0.0);
  const auto start = Clock::now();
  // One step's result, whatever computed it: the CSV row, the VTK frame and the progress.
  // `state` is null on steps whose state the backend was not asked for.
  long long done_before = 0;  // steps before the current batch
  // Whatever computed the state, a mesh turned inside out is not a result: the run fails
  // with the element, place and time (sim/element_watch.hpp), and no output is committed.
  const ElementWatch watch(model);
  HoldWatch hold_watch(model);
  auto record = [&](long long i, double plate_mm, double force_N, const State* state) {
    const double t = i * dt;
    if (!std::isfinite(force_N)) {
      throw Error("non-finite plate force at step " + std::to_string(i) + " (t = " + format(t) +
                  " s): the run is numerically unstable");
    }
    if (state) {
      watch.check(state->x, t);
      if (scenario.plate) hold_watch.check(t, plate_mm, force_N, *state);
    }
    const double surface = state ? surface_displacement_mm(model, *state, centre)
                                 : std::numeric_limits<double>::quiet_NaN();
    if (tools > 0) {
      const std::size_t at = static_cast<std::size_t>(i - done_before - 1) * tools;
      std::copy(reactions.begin() + static_cast<std::ptrdiff_t>(at),
                reactions.begin() + static_cast<std::ptrdiff_t>(at + tools), last_reactions.begin());
      for (std::size_t k = 0; k < tools; ++k) {
        const double f = last_reactions[k].force.norm();
        if (!std::isfinite(f)) {
          throw Error("non-finite reaction on tool " + model.tools[k].name + " at step " +
                      std::to_string(i) + ": the run is numerically unstable");
        }
        if (f > tool_peak[k].first) tool_peak[k] = {f, t};
      }
      write_tool_row(i);
    }
    figures.add(t, force_N, surface);
    if (t >= next_csv - slack || i == steps) {
      // A backend that keeps no state in host memory is read only at the frames; surface_mm
      // stays empty (docs/data-format.md) on the rows in between.
      csv.write_row(t, plate_mm, force_N, surface);
      if (state) write_object_row(t, *state);
      while (next_csv <= t + slack) next_csv += csv_interval;
    }
    if (state && (t >= next_vtk - slack || i == steps)) {
      vtk.write_frame(*state, plate_frame(plate_mm, force_N), tool_frames(i));
      while (next_vtk <= t + slack) next_vtk += vtk_interval;
    }
    progress.update(i);
  };

  // Batches of steps up to the next point whose state is needed: every VTK frame, and every
  // CSV row where the state costs nothing to look at (the reference).
  const bool resident = engine->resident_state() != nullptr;
  std::vector<double> plate_z;
  std::vector<ToolPose> poses;
  long long done = 0;
  while (done < steps) {
    long long end = std::min({steps, done + kMaxBatchSteps, first_step_at(next_vtk, dt, done),
                              first_step_at(next_watch, dt, done)});
    if (resident) end = std::min(end, first_step_at(next_csv, dt, done));
    plate_z.clear();
    poses.clear();
    for (long long i = done + 1; i <= end; ++i) {
      plate_z.push_back(scenario.plate_z(model, i));
      if (tools > 0) {
        const std::vector<ToolPose> p = scenario.tool_poses(i);
        poses.insert(poses.end(), p.begin(), p.end());
      }
    }
    const std::vector<double> force =
        tools > 0 ? engine->run_tools(plate_z, poses, reactions) : engine->run(plate_z);
    done_before = done;
    const bool frame_due = end == steps || end * dt >= next_vtk - slack;
    const bool watch_due = end * dt >= next_watch - slack;
    while (next_watch <= end * dt + slack) next_watch += watch_interval;
    State read_back;
    const State* end_state = engine->resident_state();
    if (!end_state && (frame_due || watch_due)) {
      read_back = engine->state();
      end_state = &read_back;
    }
    for (long long i = done + 1; i <= end; ++i) {
      record(i, scenario.plate_mm(i), force[static_cast<std::size_t>(i - done - 1)],
             i == end ? end_state : nullptr);
    }
    done = end;
  }
  progress.finish();
  const double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  csv.close();
  vtk.close();
  if (object_csv) {
    object_csv->close();
    if (!*object_csv) throw Error(dir + "/objects.csv: writing failed (disk full?)");
  }
  if (tool_csv) {
    tool_csv->close();
    if (!*tool_csv) throw Error(dir + "/tools.csv: writing failed (disk full?)");
  }

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
  if (engine_info.contains("cpu_path")) {
    std::cout << "  computed on the " << engine_info["cpu_path"].get<std::string>() << "\n";
  }
  // The plate's phases and forces; a scene without a plate has none to tell.
  if (scenario.plate) {
    for (const std::string& line : figures.lines()) std::cout << "  " << line << "\n";
  }
  for (std::size_t k = 0; k < tools; ++k) {
    std::cout << "  tool " << model.tools[k].name << ": largest reaction "
              << format(tool_peak[k].first, "%.4g") << " N at t = " << format(tool_peak[k].second, "%.4g")
              << " s\n";
  }
  std::cout << "  force CSV:  " << target << "/force.csv\n"
            << "  VTK series: " << target << "/mesh.pvd (" << vtk.frames() << " frames in "
            << target << "/vtk/, open the .pvd in ParaView)\n";
  if (objects > 1) {
    std::cout << "  objects:    " << target << "/objects.csv (centre of mass and velocity of "
              << objects << " objects)\n";
  }
  if (tools > 0) {
    std::cout << "  tools CSV:  " << target << "/tools.csv (reaction force and torque on "
              << tools << " tool" << (tools == 1 ? "" : "s") << " every step)\n";
  }
  if (const std::vector<std::string> absent = vtk.absent_arrays(); !absent.empty()) {
    std::cout << "  VTK note:   no";
    for (std::size_t i = 0; i < absent.size(); ++i) std::cout << (i ? ", " : " ") << absent[i];
    std::cout << " in the frames: the 2-D model has no depth (top area)\n";
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
  duration->check(number_in(0.0, HUGE_VAL, "a simulated time in seconds", true));
  auto* steps = add_steps_option(cmd, args->steps, "number of time steps (default: duration / dt)");
  duration->excludes(steps);
  cmd->add_flag("--quiet,-q", args->quiet, "no progress display on stderr");
  cmd->add_flag("--no-plot", args->no_plot, "do not draw plot.png (no gnuplot needed)");
  cmd->add_flag("--allow-dropped", args->allow_dropped,
                "run on a backend that leaves out features of the scenario (e.g. topology "
                "maintenance on a core); without it such a run is refused, naming them");
  cmd->add_option("--backend", args->backend,
                  "what computes the run: " + backend::backend_names() +
                      " (docs/backends.md); ref is the double reference, float the hardware's "
                      "model in single precision; bittrue, rtl and remote give identical numbers")
      ->capture_default_str()
      ->check(backend_spec());
  add_lanes_option(cmd, args->lanes, "an in-process rtl or bittrue core");
  add_cpu_options(cmd, args->cpu);
  cmd->callback([args]() { run_simulate(*args); });
}

}  // namespace rheo::cli
