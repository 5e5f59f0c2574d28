#include "host/identify/specimen.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "host/identify/object_specimen.hpp"
#include "sim/edge_kernel.hpp"
#include "sim/error.hpp"
#include "sim/relaxation_spectrum.hpp"

namespace rheo::identify {
namespace {

// The column's single edge in edge units (N/m, N s/m), with its natural length h.
struct Column {
  EdgeMaterial material;
  double h = 0.0;
  double area = 0.0;
};

// Internal states of the column's edge: z = (d, m, s_1 .. s_K) with d the Voigt length, m
// the Maxwell-arm extension and s_j the spectrum arms' extensions (K = spectrum_arms).
// Sized at run time but stored inline (no heap allocation in the time loop): at most
// d, m, the spectrum arms and the length l.
constexpr int kMaxStates = 3 + EdgeMaterial::kMaxSpectrumArms;
using VecX = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStates, 1>;
using MatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStates, kMaxStates>;

struct EdgeRates {
  double tension = 0.0;
  VecX zdot;  // rates of z
};

int state_size(const Column& c) { return 2 + c.material.spectrum_arms; }

// The reference kernel on the column: bottom particle at the origin at rest, top particle
// at height l moving up with ldot.
EdgeRates evaluate(const Column& c, double l, double ldot, const VecX& z) {
  const Vec3 xs(0.0, 0.0, 0.0), xe(0.0, 0.0, l), vs(0.0, 0.0, 0.0), ve(0.0, 0.0, ldot);
  EdgeRates r;
  r.zdot.resize(z.size());
  const int arms = c.material.spectrum_arms;
  const EdgeEval<double> e = evaluate_edge<double>(c.material, xs, xe, vs, ve, z[0], c.h, c.h,
                                                   z[1], arms > 0 ? z.data() + 2 : nullptr,
                                                   arms > 0 ? r.zdot.data() + 2 : nullptr);
  r.tension = e.tension;
  r.zdot[0] = e.ddot;
  r.zdot[1] = e.mdot;
  return r;
}

// Out of contact the massless top particle moves so that the tension vanishes. The
// tension is affine in ldot (the series viscosity depends on the spring force only), so
// two kernel evaluations give the root exactly.
double free_ldot(const Column& c, double l, const VecX& z) {
  const double t0 = evaluate(c, l, 0.0, z).tension;
  const double t1 = evaluate(c, l, 1.0, z).tension;
  const double slope = t1 - t0;
  if (!(slope > 0.0)) {
    throw Error(
        "specimen model: tension does not grow with the stretching rate (c1 = 0?); "
        "the quasi-static free phase needs a positive Voigt viscosity");
  }
  return -t0 / slope;
}

// Free-phase rates of y = (z, l).
VecX free_rates(const Column& c, const VecX& y) {
  const int n = static_cast<int>(y.size()) - 1;
  const VecX z = y.head(n);
  const double l = y[n];
  const double ld = free_ldot(c, l, z);
  VecX out(y.size());
  out.head(n) = evaluate(c, l, ld, z).zdot;
  out[n] = ld;
  return out;
}

// Contact-phase rates of z at a given length and stretching rate.
VecX contact_rates(const Column& c, double l, double ldot, const VecX& z) {
  return evaluate(c, l, ldot, z).zdot;
}

double fd_step(double v, double scale) { return 1e-7 * std::max(std::abs(v), scale); }

// Backward Euler of the free phase: y1 = y0 + dt f(y1), Newton with a finite-difference
// Jacobian taken at y0 (exact in one iteration for a linear material).
VecX free_step(const Column& c, const VecX& y0, double dt) {
  const int n = static_cast<int>(y0.size());
  const VecX f0 = free_rates(c, y0);
  MatX jac(n, n);
  for (int j = 0; j < n; ++j) {
    VecX yp = y0;
    const double hstep = fd_step(y0[j], c.h);
    yp[j] += hstep;
    jac.col(j) = (free_rates(c, yp) - f0) / hstep;
  }
  const MatX a = MatX::Identity(n, n) - dt * jac;
  const auto lu = a.partialPivLu();
  VecX y1 = y0 + lu.solve(dt * f0);
  for (int it = 0; it < 2; ++it) {
    const VecX res = y1 - y0 - dt * free_rates(c, y1);
    y1 -= lu.solve(res);
  }
  return y1;
}

// Contact phase with the length moving from l0 to l1 (constant ldot): trapezoidal rule for
// (d, m); the spectrum arms, linear and driven by ldot alone (sdot_j = ldot - s_j / tau_j,
// neither d nor m enters), take their exact solution, which keeps the Newton system at two
// unknowns however many arms there are.
VecX contact_step(const Column& c, const VecX& z0, double l0, double l1, double dt) {
  constexpr int n = 2;
  using Vec2 = Eigen::Vector2d;
  const double ldot = (l1 - l0) / dt;
  auto rates = [&](double l, const Vec2& dm) {
    VecX z = z0;
    z.head<n>() = dm;
    return Vec2(contact_rates(c, l, ldot, z).head<n>());
  };
  const Vec2 y0 = z0.head<n>();
  const Vec2 g0 = rates(l0, y0);
  const Vec2 g1 = rates(l1, y0);
  Eigen::Matrix2d jac;
  for (int j = 0; j < n; ++j) {
    Vec2 yp = y0;
    const double hstep = fd_step(y0[j], c.h);
    yp[j] += hstep;
    jac.col(j) = (rates(l1, yp) - g1) / hstep;
  }
  const Eigen::Matrix2d a = Eigen::Matrix2d::Identity() - 0.5 * dt * jac;
  const auto lu = a.partialPivLu();
  Vec2 y1 = y0 + lu.solve(0.5 * dt * (g0 + g1));
  for (int it = 0; it < 2; ++it) {
    const Vec2 res = y1 - y0 - 0.5 * dt * (g0 + rates(l1, y1));
    y1 -= lu.solve(res);
  }
  VecX z1 = z0;
  z1.head<n>() = y1;
  for (int j = 0; j < c.material.spectrum_arms; ++j) {
    const double tau = c.material.spectrum[j].c / c.material.spectrum[j].k;
    const double decay = std::exp(-dt / tau);
    z1[n + j] = z0[n + j] * decay + ldot * tau * (1.0 - decay);
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

Model coarse_model(const Geometry& g, const SpecimenParams& p) {
  const double h = g.height_m();
  const double per_length = g.area_m2() / h;  // k = E A / h, c = eta A / h
  EdgeMaterial mat = continuum_material(p);
  for (double* v : {&mat.k1, &mat.c1, &mat.c2, &mat.c2_min, &mat.k2, &mat.c3}) *v *= per_length;
  for (int j = 0; j < mat.spectrum_arms; ++j) {
    mat.spectrum[j].k *= per_length;
    mat.spectrum[j].c *= per_length;
  }
  mat.f2 *= g.area_m2();
  Model model;
  model.dim = 3;
  model.x0 = {Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, h)};
  model.mass = {0.0, 0.0};  // massless: quasi-static column (see specimen.hpp)
  model.flags = {kFixed, kPlate};
  model.gravity = Vec3::Zero();
  model.size = h;
  model.height = h;
  model.top_area = g.area_m2();
  model.materials = {mat};
  model.edges = {Edge{0, 1, h, h, 0}};
  return model;
}

EdgeMaterial continuum_material(const SpecimenParams& p) {
  EdgeMaterial mat;
  mat.k1 = p.E1;
  mat.c1 = p.c1;
  mat.c2 = p.c2;
  mat.a_min = 0.0;
  mat.a_max = 1e30;
  if (p.E2 > 0.0 && p.c3 > 0.0) {
    mat.k2 = p.E2;
    mat.c3 = p.c3;
  }
  if (p.damping_ratio > 1.0 && p.damping_stress > 0.0) {
    mat.nonlinear = true;
    mat.f1 = 0.0;
    mat.f2 = p.damping_stress;
    mat.c2_min = p.c2 / p.damping_ratio;
  }
  mat.hardening = p.hardening;
  if (p.spectrum_modulus > 0.0) {
    set_power_law_spectrum(mat, {p.spectrum_modulus, p.spectrum_alpha, p.spectrum_t_lo,
                                 p.spectrum_t_hi});
  }
  return mat;
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
    try {
      return simulate_object(protocol, p, options);
    } catch (const ObjectModelError&) {
      throw;
    } catch (const Error& e) {
      throw ObjectModelError(e.what());
    }
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
  // The spectrum arms do not bound the step: in contact they are integrated exactly
  // (contact_step), and out of contact backward Euler keeps them stable.
  const double duration = protocol.time_s.back();
  double dt_max = std::min(options.max_dt, tau_min / options.steps_per_time_constant);
  dt_max = std::max(dt_max, duration / static_cast<double>(options.max_steps));

  Prediction out;
  const std::size_t n = protocol.size();
  out.force_N.resize(n);
  out.surface_mm.resize(n);
  out.contact.resize(n);

  // At rest: Voigt length at its natural value, arms unstretched.
  const int nz = state_size(col);
  VecX z = VecX::Zero(nz);
  z[0] = h;
  double l = h;
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
        const VecX z1 = contact_step(col, z, l, l_plate, dt);
        const double ldot = (l_plate - l) / dt;
        const double f = -evaluate(col, l_plate, ldot, z1).tension;
        if (f >= 0.0) {
          l = l_plate;
          z = z1;
          force = f;
          stepped = true;
        }
      }
      if (!stepped) {
        VecX y(nz + 1);
        y << z, l;
        const VecX free = free_step(col, y, dt);
        if (l_plate < free[nz]) {
          // The plate is below where the free surface would be: it pushes.
          const VecX z1 = contact_step(col, z, l, l_plate, dt);
          const double ldot = (l_plate - l) / dt;
          l = l_plate;
          z = z1;
          force = -evaluate(col, l, ldot, z).tension;
          in_contact = true;
        } else {
          z = free.head(nz);
          l = free[nz];
          force = 0.0;
          in_contact = false;
        }
      }
      z[0] = clamp_voigt_length(col.material, z[0], l);
      if (p.lag_s > 0.0) {
        sensor += (force - sensor) * (1.0 - std::exp(-dt / p.lag_s));
      } else {
        sensor = force;
      }
      if (!std::isfinite(l) || !z.allFinite() || !std::isfinite(sensor)) {
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
