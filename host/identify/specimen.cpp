#include "host/identify/specimen.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "host/identify/object_specimen.hpp"
#include "sim/edge_kernel.hpp"
#include "sim/error.hpp"

namespace rheo::identify {
namespace {

// The column's single edge in edge units (N/m, N s/m), with its natural length h.
struct Column {
  EdgeMaterial material;
  double h = 0.0;
  double area = 0.0;
};

struct EdgeRates {
  double tension = 0.0;
  double ddot = 0.0;
  double mdot = 0.0;
};

// The reference kernel on the column: bottom particle at the origin at rest, top particle
// at height l moving up with ldot.
EdgeRates evaluate(const Column& c, double l, double ldot, double d, double m) {
  const Vec3 xs(0.0, 0.0, 0.0), xe(0.0, 0.0, l), vs(0.0, 0.0, 0.0), ve(0.0, 0.0, ldot);
  const EdgeEval<double> e = evaluate_edge<double>(c.material, xs, xe, vs, ve, d, c.h, c.h, m);
  return {e.tension, e.ddot, e.mdot};
}

// Out of contact the massless top particle moves so that the tension vanishes. The
// tension is affine in ldot (the series viscosity depends on the spring force only), so
// two kernel evaluations give the root exactly.
double free_ldot(const Column& c, double l, double d, double m) {
  const double t0 = evaluate(c, l, 0.0, d, m).tension;
  const double t1 = evaluate(c, l, 1.0, d, m).tension;
  const double slope = t1 - t0;
  if (!(slope > 0.0)) {
    throw Error(
        "specimen model: tension does not grow with the stretching rate (c1 = 0?); "
        "the quasi-static free phase needs a positive Voigt viscosity");
  }
  return -t0 / slope;
}

using Vec3d = Eigen::Vector3d;
using Vec2d = Eigen::Vector2d;

// Free-phase rates of (d, m, l).
Vec3d free_rates(const Column& c, const Vec3d& y) {
  const double ld = free_ldot(c, y[2], y[0], y[1]);
  const EdgeRates r = evaluate(c, y[2], ld, y[0], y[1]);
  return Vec3d(r.ddot, r.mdot, ld);
}

// Contact-phase rates of (d, m) at a given length and stretching rate.
Vec2d contact_rates(const Column& c, double l, double ldot, const Vec2d& z) {
  const EdgeRates r = evaluate(c, l, ldot, z[0], z[1]);
  return Vec2d(r.ddot, r.mdot);
}

double fd_step(double v, double scale) { return 1e-7 * std::max(std::abs(v), scale); }

// Backward Euler of the free phase: y1 = y0 + dt f(y1), Newton with a finite-difference
// Jacobian taken at y0 (exact in one iteration for a linear material).
Vec3d free_step(const Column& c, const Vec3d& y0, double dt) {
  const Vec3d f0 = free_rates(c, y0);
  Eigen::Matrix3d jac;
  for (int j = 0; j < 3; ++j) {
    Vec3d yp = y0;
    const double hstep = fd_step(y0[j], c.h);
    yp[j] += hstep;
    jac.col(j) = (free_rates(c, yp) - f0) / hstep;
  }
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity() - dt * jac;
  const auto lu = a.partialPivLu();
  Vec3d y1 = y0 + lu.solve(dt * f0);
  for (int it = 0; it < 2; ++it) {
    const Vec3d res = y1 - y0 - dt * free_rates(c, y1);
    y1 -= lu.solve(res);
  }
  return y1;
}

// Trapezoidal rule of the contact phase for (d, m) with the length moving from l0 to l1.
Vec2d contact_step(const Column& c, const Vec2d& z0, double l0, double l1, double dt) {
  const double ldot = (l1 - l0) / dt;
  const Vec2d g0 = contact_rates(c, l0, ldot, z0);
  const Vec2d g1 = contact_rates(c, l1, ldot, z0);
  Eigen::Matrix2d jac;
  for (int j = 0; j < 2; ++j) {
    Vec2d zp = z0;
    const double hstep = fd_step(z0[j], c.h);
    zp[j] += hstep;
    jac.col(j) = (contact_rates(c, l1, ldot, zp) - g1) / hstep;
  }
  const Eigen::Matrix2d a = Eigen::Matrix2d::Identity() - 0.5 * dt * jac;
  const auto lu = a.partialPivLu();
  Vec2d z1 = z0 + lu.solve(0.5 * dt * (g0 + g1));
  for (int it = 0; it < 2; ++it) {
    const Vec2d res = z1 - z0 - 0.5 * dt * (g0 + contact_rates(c, l1, ldot, z1));
    z1 -= lu.solve(res);
  }
  return z1;
}

Column make_column(const Geometry& g, const SpecimenParams& p) {
  const Model model = coarse_model(g, p);
  return {model.materials[0], g.height_m(), g.area_m2()};
}

void check_positive(double v, const char* name) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    std::ostringstream s;
    s << "specimen model: parameter " << name << " = " << v << ", expected a positive finite value";
    throw Error(s.str());
  }
}

}  // namespace

const std::vector<Extension>& all_extensions() {
  static const std::vector<Extension> list{
      Extension::kSecondRelaxationTime, Extension::kForceDependentDamping,
      Extension::kStrainHardening, Extension::kSensorLag, Extension::kSensorOffset};
  return list;
}

std::string cause_name(Extension e) {
  switch (e) {
    case Extension::kNone:
      return "none";
    case Extension::kSecondRelaxationTime:
      return "second_relaxation_time";
    case Extension::kForceDependentDamping:
      return "force_dependent_damping";
    case Extension::kStrainHardening:
      return "strain_hardening";
    case Extension::kSensorLag:
      return "sensor_lag";
    case Extension::kSensorOffset:
      return "sensor_offset";
  }
  return "none";
}

Extension extension_from_name(const std::string& name) {
  if (name == "none" || name == "three_element") return Extension::kNone;
  for (Extension e : all_extensions()) {
    if (cause_name(e) == name) return e;
  }
  throw Error("unknown model/cause '" + name +
              "', expected three_element, second_relaxation_time, force_dependent_damping, "
              "strain_hardening, sensor_lag or sensor_offset");
}

Model coarse_model(const Geometry& g, const SpecimenParams& p) {
  const double h = g.height_m();
  const double per_length = g.area_m2() / h;  // k = E A / h, c = eta A / h
  Model model;
  model.dim = 3;
  model.x0 = {Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, h)};
  model.mass = {0.0, 0.0};  // massless: quasi-static column (see specimen.hpp)
  model.flags = {kFixed, kPlate};
  model.gravity = Vec3::Zero();
  model.size = h;
  model.height = h;
  model.top_area = g.area_m2();
  EdgeMaterial mat;
  mat.k1 = p.E1 * per_length;
  mat.c1 = p.c1 * per_length;
  mat.c2 = p.c2 * per_length;
  mat.a_min = 0.0;
  mat.a_max = 1e30;
  if (p.E2 > 0.0 && p.c3 > 0.0) {
    mat.k2 = p.E2 * per_length;
    mat.c3 = p.c3 * per_length;
  }
  if (p.damping_ratio > 1.0 && p.damping_stress > 0.0) {
    mat.nonlinear = true;
    mat.f1 = 0.0;
    mat.f2 = p.damping_stress * g.area_m2();
    mat.c2_min = mat.c2 / p.damping_ratio;
  }
  mat.hardening = p.hardening;
  model.materials = {mat};
  model.edges = {Edge{0, 1, h, h, 0}};
  return model;
}

std::string coarse_mesh_description(const Geometry& g) {
  std::ostringstream s;
  s << "1-D column: 2 particles (bottom fixed, top under the plate), 1 three-element edge of "
       "rest length "
    << g.height_mm << " mm, k = E*A/h and c = eta*A/h with A = " << g.width_mm << " mm x "
    << g.depth_mm << " mm; massless (quasi-static) top particle";
  return s.str();
}

std::string specimen_form_name(SpecimenForm f) {
  return f == SpecimenForm::kObject ? "object" : "column";
}

ObjectMesh ObjectMesh::resolved(const Geometry& g) const {
  if (nx > 0) return *this;
  ObjectMesh m = *this;
  const double columns = std::round((nz - 1) * g.width_mm / g.height_mm);
  m.nx = static_cast<int>(std::clamp(columns, 1.0, 11.0)) + 1;
  return m;
}

ObjectMesh ObjectMesh::finer() const {
  ObjectMesh m = *this;
  ++m.nx;
  ++m.nz;
  if (dim == 3) ++m.ny;
  return m;
}

std::string ObjectMesh::text() const {
  std::ostringstream s;
  if (nx == 0) return std::to_string(dim) + "d:auto";
  s << dim << "d:" << nx << "x";
  if (dim == 3) s << ny << "x";
  s << nz;
  if (truss) s << ":truss";
  return s.str();
}

ObjectMesh parse_object_mesh(const std::string& text) {
  const std::string expected =
      "--mesh '" + text +
      "': expected 2d:auto, 2d:NXxNZ or 3d:NXxNYxNZ, optionally followed by :truss, with 2 to 12 "
      "particles per axis (e.g. 2d:3x3, 3d:3x2x3)";
  ObjectMesh m;
  std::string rest = text;
  const auto colon = rest.find(':');
  if (colon == std::string::npos) throw Error(expected);
  const std::string dim = rest.substr(0, colon);
  if (dim != "2d" && dim != "3d") throw Error(expected);
  m.dim = dim == "2d" ? 2 : 3;
  rest = rest.substr(colon + 1);
  if (rest == "auto" && m.dim == 2) return m;
  const auto tail = rest.find(':');
  if (tail != std::string::npos) {
    if (rest.substr(tail + 1) != "truss") throw Error(expected);
    m.truss = true;
    rest = rest.substr(0, tail);
  }
  std::vector<int> counts;
  std::size_t pos = 0;
  while (pos <= rest.size()) {
    const auto x = rest.find('x', pos);
    const std::string part = rest.substr(pos, x == std::string::npos ? std::string::npos : x - pos);
    if (part.empty() || part.size() > 2 ||
        part.find_first_not_of("0123456789") != std::string::npos) {
      throw Error(expected);
    }
    counts.push_back(std::stoi(part));
    if (x == std::string::npos) break;
    pos = x + 1;
  }
  if (counts.size() != static_cast<std::size_t>(m.dim)) throw Error(expected);
  for (int c : counts) {
    if (c < 2 || c > 12) throw Error(expected);
  }
  m.nx = counts.front();
  m.nz = counts.back();
  if (m.dim == 3) m.ny = counts[1];
  return m;
}

std::string specimen_description(const Geometry& g, const SimulationOptions& o) {
  if (o.form == SpecimenForm::kColumn) {
    return "first guess (not the object model): " + coarse_mesh_description(g);
  }
  const ObjectMesh m = o.mesh.resolved(g);
  std::ostringstream s;
  s << "object model: " << m.dim << "-D " << (m.truss ? "truss" : "lattice") << " of " << m.nx
    << " x ";
  if (m.dim == 3) s << m.ny << " x ";
  s << m.nz << " particles (--mesh " << m.text() << ") over the specimen " << g.width_mm
    << " mm wide, " << g.height_mm << " mm high" << (m.dim == 3 ? ", " : " and ") << g.depth_mm
    << " mm " << (m.dim == 3 ? "deep" : "thick (plane model)")
    << "; bottom layer fixed, top layer under the plate (held while it pushes), reference "
       "simulator, semi-implicit Euler with "
    << o.steps_per_sample
    << " steps per sample interval and numerical masses (docs/identify.md), no gravity";
  return s.str();
}

Prediction simulate(const Measurement& protocol, const SpecimenParams& p,
                    const SimulationOptions& options) {
  check_positive(p.E1, "E1");
  check_positive(p.c1, "c1");
  check_positive(p.c2, "c2");
  if (p.hardening < 0.0) throw Error("specimen model: hardening < 0, expected >= 0");
  if (p.lag_s < 0.0) throw Error("specimen model: lag_s < 0, expected >= 0");
  if (!(options.steps_per_sample >= 1)) {
    throw Error("specimen model: steps_per_sample must be at least 1");
  }
  if (options.form == SpecimenForm::kObject) {
    if (!(std::isfinite(options.max_dt) && options.max_dt > 0.0) ||
        !(std::isfinite(options.steps_per_time_constant) &&
          options.steps_per_time_constant > 0.0)) {
      throw Error("specimen model: max_dt and steps_per_time_constant must be finite and > 0");
    }
    return simulate_object(protocol, p, options);
  }
  // A NaN here would reach an int conversion of the step count below (undefined behaviour):
  // options are checked where they enter, whoever set them.
  if (!(std::isfinite(options.max_dt) && options.max_dt > 0.0)) {
    throw Error("specimen model: max_dt = " + std::to_string(options.max_dt) +
                " s, expected a finite time step > 0");
  }
  if (!(std::isfinite(options.steps_per_time_constant) && options.steps_per_time_constant > 0.0) ||
      options.max_steps < 1) {
    throw Error("specimen model: steps_per_time_constant and max_steps must be finite and > 0");
  }
  const Geometry& g = protocol.geometry;
  const Column col = make_column(g, p);
  const double h = col.h;
  const bool arm = col.material.has_maxwell_arm();

  // Accuracy bound on the step: a fraction of the shortest material time constant.
  double tau_min = (p.c1 + p.c2) / p.E1;
  if (arm) tau_min = std::min(tau_min, p.c3 / p.E2);
  const double duration = protocol.time_s.back();
  double dt_max = std::min(options.max_dt, tau_min / options.steps_per_time_constant);
  dt_max = std::max(dt_max, duration / static_cast<double>(options.max_steps));

  Prediction out;
  const std::size_t n = protocol.size();
  out.force_N.resize(n);
  out.surface_mm.resize(n);
  out.contact.resize(n);

  double l = h, d = h, m = 0.0;  // at rest, Voigt length at its natural value
  double t = 0.0, plate_m = 0.0;
  double sensor = 0.0;  // lagged force reading [N]
  bool in_contact = false;
  double force = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t_next = protocol.time_s[i];
    const double p_next = protocol.plate_mm[i] * 1e-3;
    const double gap = t_next - t;
    const int steps = gap > 0.0 ? static_cast<int>(std::ceil(gap / dt_max - 1e-9)) : 0;
    for (int s = 1; s <= steps; ++s) {
      const double dt = gap / steps;
      const double plate_new = plate_m + (p_next - plate_m) * s / steps;
      const double l_plate = h - plate_new;
      // Unilateral contact, quasi-static: the plate holds the top while following it takes a
      // compressive force; otherwise the top moves freely with zero tension. In contact the
      // contact step is tried first (cheap); out of contact the free step is tried first and
      // the plate takes over when it is below where the free surface would be.
      bool stepped = false;
      if (in_contact) {
        const Vec2d z = contact_step(col, Vec2d(d, m), l, l_plate, dt);
        const double ldot = (l_plate - l) / dt;
        const double f = -evaluate(col, l_plate, ldot, z[0], z[1]).tension;
        if (f >= 0.0) {
          l = l_plate;
          d = z[0];
          m = z[1];
          force = f;
          stepped = true;
        }
      }
      if (!stepped) {
        const Vec3d free = free_step(col, Vec3d(d, m, l), dt);
        if (l_plate < free[2]) {
          // The plate is below where the free surface would be: it pushes.
          const Vec2d z = contact_step(col, Vec2d(d, m), l, l_plate, dt);
          const double ldot = (l_plate - l) / dt;
          l = l_plate;
          d = z[0];
          m = z[1];
          force = -evaluate(col, l, ldot, d, m).tension;
          in_contact = true;
        } else {
          d = free[0];
          m = free[1];
          l = free[2];
          force = 0.0;
          in_contact = false;
        }
      }
      d = clamp_voigt_length(col.material, d, l);
      if (p.lag_s > 0.0) {
        sensor += (force - sensor) * (1.0 - std::exp(-dt / p.lag_s));
      } else {
        sensor = force;
      }
      if (!std::isfinite(l) || !std::isfinite(d) || !std::isfinite(m) || !std::isfinite(sensor)) {
        std::ostringstream msg;
        msg << "specimen model: non-finite state at t = " << t + dt * s
            << " s (numerical trouble; parameters E1=" << p.E1 << " c1=" << p.c1 << " c2=" << p.c2
            << ")";
        throw Error(msg.str());
      }
    }
    t = t_next;
    plate_m = p_next;
    out.force_N[i] = sensor + p.offset_N;
    out.surface_mm[i] = (h - l) * 1e3;
    out.contact[i] = in_contact;
  }
  return out;
}

}  // namespace rheo::identify
