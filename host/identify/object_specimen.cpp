#include "host/identify/object_specimen.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "host/backend/backend.hpp"
#include "sim/error.hpp"
#include "sim/mesh.hpp"
#include "sim/relaxation_spectrum.hpp"
#include "sim/simulator.hpp"
#include "sim/stable_masses.hpp"

namespace rheo::identify {
namespace {

// Share of the explicit stability bound the chosen masses use (sim/stable_masses.hpp).
constexpr double kMassSafety = kStableMassSafety;
// Largest refinement of the sample-based step for short relaxation times (see
// step_plan): a relaxation time needs at least steps_per_time_constant steps.
constexpr double kMaxHalvings = 8.0;

// Shortest material time constant of the parameters [s] (the explicit update of the edge
// states d and m must resolve it).
double shortest_time_constant(const SpecimenParams& p) {
  const double c2_min = p.damping_ratio > 1.0 ? p.c2 / p.damping_ratio : p.c2;
  double tau = (p.c1 + c2_min) / p.E1;
  if (p.E2 > 0.0 && p.c3 > 0.0) tau = std::min(tau, p.c3 / p.E2);
  if (p.spectrum_modulus > 0.0) tau = std::min(tau, fastest_spectrum_time(continuum_material(p)));
  return tau;
}

// Plate displacement [m] at time t: linear between samples, from 0 at t = 0 to the first
// sample, held after the last.
class PlateHistory {
 public:
  explicit PlateHistory(const Measurement& m) : m_(m) {}
  double at(double t) {
    const auto& ts = m_.time_s;
    while (next_ < ts.size() && ts[next_] < t) ++next_;
    if (next_ >= ts.size()) return m_.plate_mm.back() * 1e-3;
    const double t1 = ts[next_], p1 = m_.plate_mm[next_] * 1e-3;
    const double t0 = next_ == 0 ? 0.0 : ts[next_ - 1];
    const double p0 = next_ == 0 ? 0.0 : m_.plate_mm[next_ - 1] * 1e-3;
    if (!(t1 > t0)) return p1;
    return p0 + (p1 - p0) * (t - t0) / (t1 - t0);
  }

 private:
  const Measurement& m_;
  std::size_t next_ = 0;
};

}  // namespace

Model object_model(const Geometry& g, const SpecimenParams& p, const ObjectMesh& mesh_in,
                   double dt) {
  const ObjectMesh mesh = mesh_in.resolved(g);
  BlockSpec b;
  b.dim = mesh.dim;
  b.nx = mesh.nx;
  b.ny = mesh.ny;
  b.nz = mesh.nz;
  b.sx = g.width_mm * 1e-3;
  b.sy = g.depth_mm * 1e-3;
  b.sz = g.height_m();
  b.structure = mesh.truss ? Structure::kTruss : Structure::kLattice;
  // f2 is a stress here: make_block turns it into an edge force.
  b.material = continuum_material(p);
  Model model = make_block(b);
  model.gravity = Vec3::Zero();
  model.plate_contact = PlateContact::kHoldWhilePushing;

  // Masses for a stable step dt (see object_specimen.hpp): the rule a scenario's
  // "masses": "stable_step" uses too (sim/stable_masses.hpp).
  assign_stable_step_masses(model, dt, kMassSafety);
  return model;
}

StepPlan step_plan(const Measurement& protocol, const SpecimenParams& p,
                   const SimulationOptions& o) {
  StepPlan plan;
  const std::size_t n = protocol.size();
  std::vector<double> wanted(n);
  double base = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double gap = protocol.time_s[i] - (i == 0 ? 0.0 : protocol.time_s[i - 1]);
    wanted[i] = gap > 0.0 ? std::min(gap / o.steps_per_sample, o.max_dt) : o.max_dt;
    base = std::min(base, wanted[i]);
  }
  const double tau = shortest_time_constant(p);
  const double dt_tau = tau / o.steps_per_time_constant;
  // A relaxation time below a sixteenth of the sample interval is not resolved by the record
  // (it shows as an instantaneous response), and the explicit edge update would need ever
  // smaller steps for it: such parameters are refused, and a fit steps back from them.
  if (dt_tau < base / kMaxHalvings) {
    std::ostringstream msg;
    msg << "object model: shortest relaxation time " << tau
        << " s is far below the shortest sample interval (the record cannot resolve it; the "
           "model would need steps below "
        << dt_tau << " s)";
    throw Error(msg.str());
  }
  // Steps are powers of two times the smallest: a small parameter change during a fit does
  // not change the step count (a jump in the objective), and a record sampled ever more
  // sparsely (a relaxation table on a log time axis) changes its step only a few times.
  plan.dt.resize(n);
  plan.smallest = std::numeric_limits<double>::infinity();
  double t = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dt = std::min(wanted[i], dt_tau);
    plan.dt[i] = base * std::exp2(std::floor(std::log2(dt / base) + 1e-12));
    plan.smallest = std::min(plan.smallest, plan.dt[i]);
    plan.steps += std::ceil((protocol.time_s[i] - t) / plan.dt[i]);
    t = protocol.time_s[i];
  }
  return plan;
}

Prediction simulate_object(const Measurement& protocol, const SpecimenParams& p,
                           const SimulationOptions& o) {
  backend::Options options;
  options.cpu = o.cpu;
  const std::unique_ptr<backend::Backend> reference = backend::make_backend("ref", options);
  return simulate_object(protocol, p, o, *reference);
}

Prediction simulate_object(const Measurement& protocol, const SpecimenParams& p,
                           const SimulationOptions& o, backend::Backend& engine) {
  const StepPlan plan = step_plan(protocol, p, o);
  if (!(plan.steps <= static_cast<double>(o.max_object_steps))) {
    std::ostringstream msg;
    msg << "object model: " << plan.steps << " steps (smallest " << plan.smallest << " s) for "
        << protocol.time_s.back() << " s of record exceed the limit of " << o.max_object_steps
        << " (the column model, --model-form column, has no such limit)";
    throw Error(msg.str());
  }
  // The masses belong to the step (see object_specimen.hpp): when the step changes, the
  // simulation continues from the same state with the masses of the new step.
  double loaded_dt = 0.0;
  Model model;
  auto start = [&](double dt) {
    const bool first = loaded_dt == 0.0;
    model = object_model(protocol.geometry, p, o.mesh, dt);
    engine.load(model, first ? initial_state(model) : engine.state(), dt);
    loaded_dt = dt;
  };
  start(plan.dt.front());
  std::vector<int> top;
  for (int i = 0; i < model.num_particles(); ++i) {
    if (model.flags[i] == kPlate) top.push_back(i);
  }
  const double h = model.height;
  // The top surface after the last step; read in place where the backend keeps its state
  // in host memory (the reference, which runs the fits), read back elsewhere.
  auto surface_now = [&]() {
    State read_back;
    const State* st = engine.resident_state();
    if (!st) {
      read_back = engine.state();
      st = &read_back;
    }
    double z = 0.0;
    for (int i : top) z += st->x[i].z();
    return (h - z / static_cast<double>(top.size())) * 1e3;
  };

  Prediction out;
  const std::size_t n = protocol.size();
  out.force_N.resize(n);
  out.surface_mm.resize(n);
  out.contact.resize(n);
  PlateHistory plate(protocol);
  double sensor = 0.0, sensor_prev = 0.0;
  double surface = 0.0, surface_prev = 0.0;
  bool contact = false;
  double t = 0.0;
  std::size_t next = 0;
  // Samples at t <= 0 read the unloaded specimen.
  while (next < n && protocol.time_s[next] <= 0.0) {
    out.force_N[next] = p.offset_N;
    out.surface_mm[next] = 0.0;
    out.contact[next] = false;
    ++next;
  }
  std::vector<double> plate_z;
  while (next < n) {
    const double dt = plan.dt[next];
    if (dt != loaded_dt) start(dt);
    // The steps up to the one that reaches the next sample, run as one batch.
    plate_z.clear();
    double t_end = t;
    do {
      t_end += dt;
      plate_z.push_back(h - plate.at(t_end));
    } while (!(protocol.time_s[next] <= t_end + 1e-9 * dt));
    const double gain = p.lag_s > 0.0 ? 1.0 - std::exp(-dt / p.lag_s) : 1.0;
    std::vector<double> force;
    if (plate_z.size() > 1) {
      force = engine.run(std::span<const double>(plate_z).first(plate_z.size() - 1));
      surface = surface_now();
    }
    const std::vector<double> last = engine.run(std::span<const double>(plate_z).last(1));
    force.push_back(last.front());
    for (std::size_t k = 0; k < force.size(); ++k) {
      sensor_prev = sensor;
      sensor += (force[k] - sensor) * gain;
    }
    surface_prev = surface;
    surface = surface_now();
    // The plate force is exactly 0 N when the plate holds no particle.
    contact = force.back() != 0.0;
    const double t_prev = t_end - dt;
    // Samples between the last step and this one: linear in time between the two.
    while (next < n && protocol.time_s[next] <= t_end + 1e-9 * dt) {
      const double w = std::clamp((protocol.time_s[next] - t_prev) / dt, 0.0, 1.0);
      out.force_N[next] = sensor_prev + w * (sensor - sensor_prev) + p.offset_N;
      out.surface_mm[next] = surface_prev + w * (surface - surface_prev);
      out.contact[next] = contact;
      ++next;
    }
    t = t_end;
  }
  return out;
}

}  // namespace rheo::identify
