#include "host/fixedcmp/compare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "host/backend/backend.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::fixedcmp {
namespace {

using nlohmann::json;

struct Tracker {
  std::string name;  // the spec with ':' -> '_': a file-name part of the plot data
  std::unique_ptr<backend::Backend> backend;
  bool alive = true;
  bool refused = false;  // before the run (load or the plate path): never stepped
  std::string error;
  long long steps_reached = 0;
  double max_pos_rel = 0.0;      // running max over particles and steps
  double max_force_err_N = 0.0;  // running max over steps
  double force_sq_sum = 0.0;
  json checkpoints = json::array();
  json samples = json::array();  // [step, max_rel, rms_rel, mean_dz_rel]
  json force_curve = json::array();
  double last_force = 0.0;
};

// One step of a backend: the plate force.
double step(backend::Backend& b, double plate_z) { return b.run(std::span(&plate_z, 1)).front(); }

}  // namespace

json compare(const Scenario& scenario, const std::vector<std::string>& specs,
             const CompareOptions& options) {
  if (options.steps < 1) throw Error("fixed: --steps must be >= 1");
  // The model of the core that computes the scenario's edges (driver::edge_element_for: the
  // damper, hardening and arms are kept when the scenario has them); the backends below
  // choose the same core from it.
  std::vector<std::string> dropped;
  const Model full = scenario.build_model();
  const Model model = driver::hardware_model(full, &dropped, driver::edge_element_for(full));
  const std::unique_ptr<backend::Backend> reference = backend::make_backend("ref");
  const State initial = initial_state(model);
  reference->load(model, initial, scenario.options);
  const double dt = scenario.options.dt;
  const double size = model.size;
  const int n = model.num_particles();

  // The whole plate path (from its height at t = 0): a backend that cannot resolve the
  // plate force along it refuses before the first step (Backend::check_plate_heights).
  std::vector<double> path;
  path.reserve(static_cast<std::size_t>(options.steps) + 1);
  for (long long s = 0; s <= options.steps; ++s) path.push_back(scenario.plate_z(model, s));

  backend::Options backend_options;
  backend_options.lanes = options.lanes;
  std::vector<Tracker> trackers;
  for (const std::string& spec : specs) {
    Tracker t;
    t.name = spec;
    std::replace(t.name.begin(), t.name.end(), ':', '_');
    t.backend = backend::make_backend(spec, backend_options);
    // A format that cannot represent the model refuses it (its range, a gravity word that
    // rounds away, a plate force it cannot resolve): that column is reported as refused,
    // with the reason, and the others run.
    try {
      t.backend->load(model, initial, scenario.options);
      t.backend->check_plate_heights(path);
    } catch (const Error& e) {
      t.alive = false;
      t.refused = true;
      t.error = std::string("refused before the run: ") + e.what();
    }
    trackers.push_back(std::move(t));
  }

  // Error-vs-step samples: every step up to 10, then plot_points_per_decade per decade.
  std::vector<long long> sample_steps;
  for (long long s = 1; s <= options.steps;) {
    sample_steps.push_back(s);
    const long long next =
        static_cast<long long>(std::ceil(s * std::pow(10.0, 1.0 / options.plot_points_per_decade)));
    s = std::max(s + 1, next);
  }
  if (sample_steps.back() != options.steps) sample_steps.push_back(options.steps);
  std::size_t next_sample = 0;
  const long long force_stride =
      std::max<long long>(1, options.steps / std::max(1, options.force_curve_points));

  json ref_force_curve = json::array();
  double peak_ref_force = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (long long s = 1; s <= options.steps; ++s) {
    const double t = s * dt;
    const double plate_z = scenario.plate_z(model, s);
    const double f_ref = step(*reference, plate_z);
    peak_ref_force = std::max(peak_ref_force, std::abs(f_ref));
    const bool is_checkpoint = std::find(options.checkpoints.begin(), options.checkpoints.end(),
                                         s) != options.checkpoints.end() ||
                               s == options.steps;
    const bool is_sample = next_sample < sample_steps.size() && sample_steps[next_sample] == s;
    if (is_sample) ++next_sample;
    const bool is_force_sample = s % force_stride == 0;
    if (is_force_sample) ref_force_curve.push_back({s, t, f_ref});
    const State& rs = *reference->resident_state();
    for (Tracker& tr : trackers) {
      if (!tr.alive) continue;
      double f = 0.0;
      State bs;
      try {
        f = step(*tr.backend, plate_z);
        bs = tr.backend->state();
      } catch (const Error& e) {
        tr.alive = false;
        tr.error = e.what();
        continue;
      }
      if (!std::isfinite(f)) {
        tr.alive = false;
        tr.error = tr.name + ": non-finite plate force at step " + std::to_string(s);
        continue;
      }
      tr.steps_reached = s;
      tr.last_force = f;
      double max_e = 0.0, sq = 0.0, dz = 0.0;
      for (int i = 0; i < n; ++i) {
        double e2 = 0.0;
        for (int c = 0; c < 3; ++c) {
          const double d = bs.x[i][c] - rs.x[i][c];
          e2 += d * d;
          if (c == 2) dz += d;
        }
        max_e = std::max(max_e, std::sqrt(e2));
        sq += e2;
      }
      const double max_rel = max_e / size;
      const double rms_rel = std::sqrt(sq / n) / size;
      const double mean_dz_rel = dz / n / size;
      if (!std::isfinite(max_rel)) {
        tr.alive = false;
        tr.error = tr.name + ": non-finite position at step " + std::to_string(s);
        continue;
      }
      tr.max_pos_rel = std::max(tr.max_pos_rel, max_rel);
      const double ferr = std::abs(f - f_ref);
      tr.max_force_err_N = std::max(tr.max_force_err_N, ferr);
      tr.force_sq_sum += ferr * ferr;
      if (is_checkpoint) {
        tr.checkpoints.push_back({{"step", s},
                                  {"max_position_error_rel", max_rel},
                                  {"max_position_error_rel_so_far", tr.max_pos_rel},
                                  {"rms_position_error_rel", rms_rel},
                                  {"mean_z_offset_rel", mean_dz_rel},
                                  {"plate_force_error_max_N", tr.max_force_err_N},
                                  {"plate_force_error_rms_N", std::sqrt(tr.force_sq_sum / s)}});
      }
      if (is_sample) tr.samples.push_back({s, max_rel, rms_rel, mean_dz_rel});
      if (is_force_sample) tr.force_curve.push_back({s, t, f});
    }
    if (options.progress) options.progress(s);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The force bound is relative to the reference's peak plate force: with no force at all
  // (a run that ends before the plate touches) every format "met" it by 0 of 0 N.
  if (!(peak_ref_force > 0.0)) {
    throw Error("fixed: the plate force is 0 N in all " + std::to_string(options.steps) +
                " steps of the reference, so the force bound (relative to its peak) cannot judge "
                "a format; run enough steps for the plate to push (--steps, or the scenario's "
                "whole protocol)");
  }

  json backends = json::array();
  for (Tracker& tr : trackers) {
    const double force_scale = peak_ref_force > 0.0 ? peak_ref_force : 1.0;
    for (json& c : tr.checkpoints) {
      c["plate_force_error_max_rel"] = c["plate_force_error_max_N"].get<double>() / force_scale;
      c["plate_force_error_rms_rel"] = c["plate_force_error_rms_N"].get<double>() / force_scale;
    }
    json b = tr.backend->describe();
    b["name"] = tr.name;
    b["steps_reached"] = tr.steps_reached;
    b["completed"] = tr.alive;
    b["refused"] = tr.refused;
    if (!tr.alive) b["error"] = tr.error;
    b["max_position_error_rel"] = tr.max_pos_rel;
    b["plate_force_error_max_N"] = tr.max_force_err_N;
    b["plate_force_error_max_rel"] = tr.max_force_err_N / force_scale;
    b["plate_force_error_rms_N"] =
        tr.steps_reached > 0 ? std::sqrt(tr.force_sq_sum / tr.steps_reached) : 0.0;
    b["checkpoints"] = tr.checkpoints;
    b["error_samples"] = tr.samples;
    b["force_curve"] = tr.force_curve;
    backends.push_back(b);
  }
  return {{"scenario", scenario.name},
          {"steps", options.steps},
          {"dt_s", dt},
          {"particles", n},
          {"edges", model.num_edges()},
          {"object_size_m", size},
          {"reference", "rheo::Simulator (double, semi-implicit Euler) on the hardware model"},
          {"dropped_features", dropped},
          {"peak_reference_plate_force_N", peak_ref_force},
          {"reference_force_curve", ref_force_curve},
          {"wall_seconds", seconds},
          {"backends", backends}};
}

void judge(json& result, const Bounds& bounds) {
  result["position_bound_rel"] = bounds.position_rel;
  result["force_bound_rel"] = bounds.force_rel;
  for (json& b : result["backends"]) {
    json failures = json::array();
    if (!b["completed"].get<bool>()) {
      failures.push_back(b.value("refused", false) ? "refused before the run" : "stopped");
    }
    const double pos = b["max_position_error_rel"].get<double>();
    const double force = b["plate_force_error_max_rel"].get<double>();
    if (!(pos <= bounds.position_rel)) {
      failures.push_back("position error " + std::to_string(pos) + " of the size > " +
                         std::to_string(bounds.position_rel));
    }
    if (!(force <= bounds.force_rel)) {
      failures.push_back("plate force error " + std::to_string(force) + " of the peak > " +
                         std::to_string(bounds.force_rel));
    }
    b["meets_bounds"] = failures.empty();
    b["bound_failures"] = failures;
  }
}

}  // namespace rheo::fixedcmp
