#include "tests/identify/continuum_body.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace rheo::testing {
namespace {

using Vec3 = Eigen::Vector3d;
using SpMat = Eigen::SparseMatrix<double>;

// Upper bound of the internal step; the rule in continuum_step_s tightens it for fast
// materials. Both linear parts are integrated exactly for a strain that is linear within the
// step, so the step only has to resolve the lagged nonlinear coefficients, contact switching
// and free recovery (where the strain is not linear in time).
constexpr double kMaxStepS = 0.002;
// Floor of the step, so a near-elastic Voigt part (eta1 -> 0) cannot ask for millions of
// steps. Below it the exact integration still holds in contact, and its decay factors tend to
// 0 rather than overshoot, so free recovery faster than the step is simply immediate.
constexpr double kMinStepS = 1e-4;
constexpr int kArmsPerDecade = 5;
constexpr int kMinSpectrumArms = 12;

// Plane-stress elasticity matrix for unit Young's modulus, engineering shear strain.
Eigen::Matrix3d unit_plane_stress(double nu) {
  Eigen::Matrix3d c;
  c << 1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu);
  return c / (1.0 - nu * nu);
}

double von_mises_plane_stress(const Vec3& s) {
  return std::sqrt(std::max(0.0, s(0) * s(0) - s(0) * s(1) + s(1) * s(1) + 3.0 * s(2) * s(2)));
}

bool is_nonlinear(const ContinuumMaterial& m) {
  return m.hardening != 0.0 || (m.damping_stress > 0.0 && m.damping_ratio > 1.0);
}

double series_viscosity(const ContinuumMaterial& m, double spring_stress) {
  if (m.damping_stress <= 0.0 || m.damping_ratio <= 1.0) return m.eta2;
  if (spring_stress >= m.damping_stress) return m.eta2 / m.damping_ratio;
  return m.eta2 * std::exp(-std::log(m.damping_ratio) * spring_stress / m.damping_stress);
}

void validate(const ContinuumBody& b, const PlateProtocol& p, double noise_N) {
  const ContinuumMaterial& m = b.m;
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("continuum body: ") + what);
  };
  require(b.width_mm > 0 && b.height_mm > 0 && b.depth_mm > 0, "dimensions must be > 0");
  require(b.nx >= 1 && b.nz >= 1, "need at least one element each way");
  require(m.E1 > 0 && m.eta2 > 0 && m.eta1 >= 0, "need E1 > 0, eta2 > 0, eta1 >= 0");
  require(m.nu > -1.0 && m.nu < 0.5, "Poisson ratio must lie in (-1, 0.5)");
  require(m.E_arm >= 0 && (m.E_arm == 0 || m.eta_arm > 0), "second arm needs eta_arm > 0");
  require(m.spectrum_G >= 0, "spectrum_G must be >= 0");
  require(m.spectrum_G == 0 || (m.spectrum_tau_lo > 0 && m.spectrum_tau_hi > m.spectrum_tau_lo),
          "spectrum needs 0 < tau_lo < tau_hi");
  require(m.hardening >= 0 && m.lag_s >= 0, "hardening and lag must be >= 0");
  require(p.depth_mm >= 0 && p.push_mm_s > 0 && p.release_mm_s > 0 && p.hold_s >= 0 &&
              p.after_s >= 0 && p.rate_hz > 0,
          "protocol needs depth >= 0, rates > 0, times >= 0");
  require(noise_N >= 0, "noise must be >= 0");
}

// One integration point with its strain-displacement matrix and volume weight; the
// material state lives beside it in the Body.
struct GaussPoint {
  std::array<int, 8> dofs;
  Eigen::Matrix<double, 3, 8> B;
  Eigen::Matrix<double, 8, 3> BtC0dV;  // B^T C(1, nu) dV
  Eigen::Matrix<double, 8, 8> K0;      // B^T C(1, nu) B dV
};

// Position of (row, col) among the stored values of a compressed column-major matrix.
int value_index(const SpMat& a, int row, int col) {
  for (int p = a.outerIndexPtr()[col]; p < a.outerIndexPtr()[col + 1]; ++p) {
    if (a.innerIndexPtr()[p] == row) return p;
  }
  throw std::logic_error("continuum body: entry outside the sparsity pattern");
}

// The displacement constraints of one contact state and the factorised reduced matrix.
// The reduced pattern is fixed, so refreshing it is a copy through `from_full`, not a
// rebuild; that keeps the per-step refactorisation of the nonlinear materials cheap.
struct Constraint {
  std::vector<int> index;  // dof -> reduced index, -1 when prescribed
  int n_free = 0;
  SpMat kff;
  std::vector<std::pair<int, int>> from_full;  // (value in K, value in kff)
  Eigen::SimplicialLDLT<SpMat> solver;
  bool analysed = false;
  long factor_version = -1;
};

class Body {
 public:
  Body(const ContinuumBody& b, double dt) : b_(b), m_(b.m), dt_(dt), arms_(maxwell_arms(b.m)) {
    c0_ = unit_plane_stress(m_.nu);
    nonlinear_ = is_nonlinear(m_);
    build_mesh();
    n_gp_ = static_cast<int>(gps_.size());
    eps_.assign(n_gp_, Vec3::Zero());
    ev_.assign(n_gp_, Vec3::Zero());
    arm_q_.assign(static_cast<std::size_t>(n_gp_) * arms_.size(), Vec3::Zero());
    tangent_.assign(n_gp_, 0.0);
    ev_gain_.assign(n_gp_, 0.0);
    ev_decay_.assign(n_gp_, 0.0);
    spring_hist_.assign(n_gp_, 0.0);
    u_ = Eigen::VectorXd::Zero(n_dof_);
    build_pattern();
    for (const MaxwellArm& a : arms_) {
      const double one_minus = -std::expm1(-dt_ / a.tau_s);
      arm_decay_.push_back(1.0 - one_minus);
      arm_gain_.push_back(a.modulus_Pa * a.tau_s * one_minus / dt_);
    }
    build_constraint(free_, false);
    build_constraint(contact_, true);
  }

  // Advances one step to a plate at plate_m (downward, metres); returns the plate force
  // (compression positive, exactly 0 with the plate off the body).
  double step(double plate_m, double t_next) {
    update_coefficients();
    const Eigen::VectorXd r = history_force();
    double force = 0.0;
    Eigen::VectorXd du;
    if (in_contact_) {
      du = solve(contact_, r, contact_increment(plate_m));
      force = plate_force(du, r);
      if (force < 0.0) {  // the plate cannot pull: it lifts off this step
        in_contact_ = false;
        du = solve(free_, r, Eigen::VectorXd::Zero(n_dof_));
        force = 0.0;
      }
    } else {
      du = solve(free_, r, Eigen::VectorXd::Zero(n_dof_));
      // The plate catches the body when it reaches the free top's highest point.
      double highest = std::numeric_limits<double>::infinity();
      for (int n : top_nodes_) highest = std::min(highest, -(u_(2 * n + 1) + du(2 * n + 1)));
      if (plate_m >= highest) {
        Eigen::VectorXd du_c = solve(contact_, r, contact_increment(plate_m));
        const double f_c = plate_force(du_c, r);
        if (f_c >= 0.0) {
          in_contact_ = true;
          du = std::move(du_c);
          force = f_c;
        }
      }
    }
    if (!du.allFinite() || !std::isfinite(force)) {
      std::ostringstream msg;
      msg << "continuum body: state not finite at t = " << t_next << " s";
      throw std::runtime_error(msg.str());
    }
    commit(du);
    return force;
  }

  // Downward displacement of the top centre (metres).
  double surface_m() const {
    const int k = b_.nz, mid = b_.nx / 2;
    // 0.0 - x rather than -x: an untouched body must print as 0, not -0.
    if (b_.nx % 2 == 0) return 0.0 - u_(2 * node(mid, k) + 1);
    return 0.0 - 0.5 * (u_(2 * node(mid, k) + 1) + u_(2 * node(mid + 1, k) + 1));
  }

 private:
  int node(int i, int k) const { return k * (b_.nx + 1) + i; }

  void build_mesh() {
    const double w = b_.width_mm * 1e-3, h = b_.height_mm * 1e-3, d = b_.depth_mm * 1e-3;
    const double hx = w / b_.nx, hz = h / b_.nz;
    n_dof_ = 2 * (b_.nx + 1) * (b_.nz + 1);
    const double g = 1.0 / std::sqrt(3.0);
    const std::array<double, 4> xi_a{-1, 1, 1, -1}, eta_a{-1, -1, 1, 1};
    for (int k = 0; k < b_.nz; ++k) {
      for (int i = 0; i < b_.nx; ++i) {
        const std::array<int, 4> nodes{node(i, k), node(i + 1, k), node(i + 1, k + 1),
                                       node(i, k + 1)};
        std::array<double, 4> x, z;
        for (int a = 0; a < 4; ++a) {
          x[a] = (i + (a == 1 || a == 2 ? 1 : 0)) * hx;
          z[a] = (k + (a >= 2 ? 1 : 0)) * hz;
        }
        for (double eta : {-g, g}) {
          for (double xi : {-g, g}) {
            std::array<double, 4> dxi, deta;
            for (int a = 0; a < 4; ++a) {
              dxi[a] = 0.25 * xi_a[a] * (1 + eta * eta_a[a]);
              deta[a] = 0.25 * eta_a[a] * (1 + xi * xi_a[a]);
            }
            Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
            for (int a = 0; a < 4; ++a) {
              J(0, 0) += dxi[a] * x[a];
              J(0, 1) += dxi[a] * z[a];
              J(1, 0) += deta[a] * x[a];
              J(1, 1) += deta[a] * z[a];
            }
            const Eigen::Matrix2d Ji = J.inverse();
            GaussPoint gp;
            gp.B.setZero();
            for (int a = 0; a < 4; ++a) {
              const double dx = Ji(0, 0) * dxi[a] + Ji(0, 1) * deta[a];
              const double dz = Ji(1, 0) * dxi[a] + Ji(1, 1) * deta[a];
              gp.B(0, 2 * a) = dx;
              gp.B(1, 2 * a + 1) = dz;
              gp.B(2, 2 * a) = dz;
              gp.B(2, 2 * a + 1) = dx;
              gp.dofs[2 * a] = 2 * nodes[a];
              gp.dofs[2 * a + 1] = 2 * nodes[a] + 1;
            }
            const double dV = J.determinant() * d;  // Gauss weights are 1
            gp.BtC0dV = gp.B.transpose() * c0_ * dV;
            gp.K0 = gp.BtC0dV * gp.B;
            gps_.push_back(gp);
          }
        }
      }
    }
    for (int i = 0; i <= b_.nx; ++i) top_nodes_.push_back(node(i, b_.nz));
  }

  void build_constraint(Constraint& c, bool contact) const {
    std::vector<bool> fixed(n_dof_, false);
    for (int i = 0; i <= b_.nx; ++i) {
      fixed[2 * node(i, 0) + 1] = true;
      if (b_.bonded) fixed[2 * node(i, 0)] = true;
    }
    // Frictionless platens leave only a rigid x translation to remove; pinning the bottom
    // centre keeps the deformation symmetric.
    if (!b_.bonded) fixed[2 * node(b_.nx / 2, 0)] = true;
    if (contact) {
      for (int n : top_nodes_) {
        fixed[2 * n + 1] = true;
        if (b_.bonded) fixed[2 * n] = true;
      }
    }
    c.index.assign(n_dof_, -1);
    c.n_free = 0;
    for (int dof = 0; dof < n_dof_; ++dof) {
      if (!fixed[dof]) c.index[dof] = c.n_free++;
    }
    std::vector<Eigen::Triplet<double>> trip;
    for (int col = 0; col < n_dof_; ++col) {
      if (c.index[col] < 0) continue;
      for (SpMat::InnerIterator it(K_, col); it; ++it) {
        if (c.index[it.row()] >= 0) trip.emplace_back(c.index[it.row()], c.index[col], 0.0);
      }
    }
    c.kff.resize(c.n_free, c.n_free);
    c.kff.setFromTriplets(trip.begin(), trip.end());
    for (int col = 0; col < n_dof_; ++col) {
      if (c.index[col] < 0) continue;
      for (int p = K_.outerIndexPtr()[col]; p < K_.outerIndexPtr()[col + 1]; ++p) {
        const int row = K_.innerIndexPtr()[p];
        if (c.index[row] >= 0) {
          c.from_full.emplace_back(p, value_index(c.kff, c.index[row], c.index[col]));
        }
      }
    }
  }

  void build_pattern() {
    std::vector<Eigen::Triplet<double>> trip;
    for (const GaussPoint& gp : gps_) {
      for (int a = 0; a < 8; ++a) {
        for (int c = 0; c < 8; ++c) trip.emplace_back(gp.dofs[a], gp.dofs[c], 0.0);
      }
    }
    K_.resize(n_dof_, n_dof_);
    K_.setFromTriplets(trip.begin(), trip.end());
    slot_.reserve(gps_.size() * 64);
    for (const GaussPoint& gp : gps_) {
      for (int c = 0; c < 8; ++c) {
        for (int a = 0; a < 8; ++a) slot_.push_back(value_index(K_, gp.dofs[a], gp.dofs[c]));
      }
    }
  }

  // Prescribed increments in contact: the top follows the plate in z. Bonded top nodes stick
  // in x where contact found them, so their x increment is 0 either way.
  Eigen::VectorXd contact_increment(double plate_m) const {
    Eigen::VectorXd du = Eigen::VectorXd::Zero(n_dof_);
    for (int n : top_nodes_) du(2 * n + 1) = -plate_m - u_(2 * n + 1);
    return du;
  }

  // Per-point coefficients of the step (start-of-step values for the nonlinear effects):
  // stress at the end of the step = tangent * d(strain) + history.
  void update_coefficients() {
    if (coefficients_ready_ && !nonlinear_) return;
    for (int g = 0; g < n_gp_; ++g) {
      double E = m_.E1;
      if (m_.hardening != 0.0) {
        // Energy-equivalent strain: sqrt(eps . C(1,nu) eps) is |eps_zz| in uniaxial stress,
        // so the hardening law matches the lumped E (1 + h eps^2) on a free-sliding block.
        const double e2 = std::max(0.0, eps_[g].dot(c0_ * eps_[g]));
        E *= 1.0 + m_.hardening * e2;
      }
      const double eta2 = series_viscosity(m_, von_mises_plane_stress(E * (c0_ * ev_[g])));
      // Voigt strain under a constant strain rate r: ev' = beta r - ev / tau, integrated
      // exactly; the three-element stress is beta (eta1 r + E ev).
      const double tau = (m_.eta1 + eta2) / E, beta = eta2 / (m_.eta1 + eta2);
      const double one_minus = -std::expm1(-dt_ / tau);
      ev_decay_[g] = 1.0 - one_minus;
      ev_gain_[g] = eta2 / E * one_minus / dt_;
      spring_hist_[g] = beta * E * ev_decay_[g];
      double tangent = beta * (m_.eta1 + eta2 * one_minus) / dt_;
      for (double a : arm_gain_) tangent += a;
      tangent_[g] = tangent;
    }
    coefficients_ready_ = true;
    assemble_stiffness();
  }

  void assemble_stiffness() {
    double* v = K_.valuePtr();
    std::fill(v, v + K_.nonZeros(), 0.0);
    for (int g = 0; g < n_gp_; ++g) {
      const double* k0 = gps_[g].K0.data();  // column-major, like slot_
      const int* slot = slot_.data() + static_cast<std::size_t>(g) * 64;
      for (int e = 0; e < 64; ++e) v[slot[e]] += tangent_[g] * k0[e];
    }
    ++k_version_;
  }

  Eigen::VectorXd history_force() const {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n_dof_);
    const std::size_t n_arms = arms_.size();
    for (int g = 0; g < n_gp_; ++g) {
      Vec3 hist = spring_hist_[g] * ev_[g];
      const Vec3* q = arm_q_.data() + static_cast<std::size_t>(g) * n_arms;
      for (std::size_t j = 0; j < n_arms; ++j) hist += arm_decay_[j] * q[j];
      const Eigen::Matrix<double, 8, 1> fe = gps_[g].BtC0dV * hist;
      for (int a = 0; a < 8; ++a) r(gps_[g].dofs[a]) += fe(a);
    }
    return r;
  }

  void factorise(Constraint& c) {
    if (c.factor_version == k_version_) return;
    double* v = c.kff.valuePtr();
    for (const auto& [full, reduced] : c.from_full) v[reduced] = K_.valuePtr()[full];
    if (!c.analysed) {
      c.solver.analyzePattern(c.kff);
      c.analysed = true;
    }
    c.solver.factorize(c.kff);
    if (c.solver.info() != Eigen::Success) {
      throw std::runtime_error("continuum body: stiffness factorisation failed");
    }
    c.factor_version = k_version_;
  }

  Eigen::VectorXd solve(Constraint& c, const Eigen::VectorXd& r, const Eigen::VectorXd& du_p) {
    factorise(c);
    const Eigen::VectorXd rhs_full = -(r + K_ * du_p);
    Eigen::VectorXd rhs(c.n_free);
    for (int dof = 0; dof < n_dof_; ++dof) {
      if (c.index[dof] >= 0) rhs(c.index[dof]) = rhs_full(dof);
    }
    const Eigen::VectorXd x = c.solver.solve(rhs);
    Eigen::VectorXd du = du_p;
    for (int dof = 0; dof < n_dof_; ++dof) {
      if (c.index[dof] >= 0) du(dof) = x(c.index[dof]);
    }
    return du;
  }

  // Sum of the top z reactions, i.e. the force the body puts on the plate.
  double plate_force(const Eigen::VectorXd& du, const Eigen::VectorXd& r) const {
    double f = 0.0;
    for (int n : top_nodes_) {
      const int dof = 2 * n + 1;
      f -= K_.col(dof).dot(du) + r(dof);  // K symmetric: column = row
    }
    return f;
  }

  void commit(const Eigen::VectorXd& du) {
    u_ += du;
    const std::size_t n_arms = arms_.size();
    for (int g = 0; g < n_gp_; ++g) {
      Eigen::Matrix<double, 8, 1> due;
      for (int a = 0; a < 8; ++a) due(a) = du(gps_[g].dofs[a]);
      const Vec3 deps = gps_[g].B * due;
      ev_[g] = ev_decay_[g] * ev_[g] + ev_gain_[g] * deps;
      Vec3* q = arm_q_.data() + static_cast<std::size_t>(g) * n_arms;
      for (std::size_t j = 0; j < n_arms; ++j) q[j] = arm_decay_[j] * q[j] + arm_gain_[j] * deps;
      eps_[g] += deps;
    }
  }

  const ContinuumBody b_;
  const ContinuumMaterial m_;
  const double dt_;
  const std::vector<MaxwellArm> arms_;
  Eigen::Matrix3d c0_;
  bool nonlinear_ = false;
  int n_dof_ = 0, n_gp_ = 0;
  std::vector<GaussPoint> gps_;
  std::vector<int> top_nodes_;
  // Material state per Gauss point: total strain, Voigt strain, arm stresses (C(1,nu)-scaled).
  std::vector<Vec3> eps_, ev_, arm_q_;
  std::vector<double> arm_decay_, arm_gain_;
  std::vector<double> tangent_, ev_gain_, ev_decay_, spring_hist_;
  bool coefficients_ready_ = false;
  SpMat K_;
  std::vector<int> slot_;  // K_ value of each Gauss point's K0 entry (column-major)
  long k_version_ = 0;
  Constraint free_, contact_;
  Eigen::VectorXd u_;
  bool in_contact_ = true;  // the plate starts touching the top
};

}  // namespace

std::vector<MaxwellArm> maxwell_arms(const ContinuumMaterial& m) {
  std::vector<MaxwellArm> arms;
  if (m.E_arm > 0.0) arms.push_back({m.eta_arm / m.E_arm, m.E_arm});
  if (m.spectrum_G > 0.0) {
    const double decades = std::log10(m.spectrum_tau_hi / m.spectrum_tau_lo);
    const int n = std::max(kMinSpectrumArms,
                           static_cast<int>(std::ceil(kArmsPerDecade * decades - 1e-9)) + 1);
    std::vector<MaxwellArm> spec;
    double g_at_1s = 0.0;
    for (int j = 0; j < n; ++j) {
      const double tau = m.spectrum_tau_lo * std::pow(m.spectrum_tau_hi / m.spectrum_tau_lo,
                                                      static_cast<double>(j) / (n - 1));
      const double w = std::pow(tau, -m.spectrum_alpha);
      spec.push_back({tau, w});
      g_at_1s += w * std::exp(-1.0 / tau);
    }
    for (MaxwellArm& a : spec) a.modulus_Pa *= m.spectrum_G / g_at_1s;
    arms.insert(arms.end(), spec.begin(), spec.end());
  }
  return arms;
}

double continuum_step_s(const ContinuumMaterial& m, double rate_hz) {
  double tau_min = std::numeric_limits<double>::infinity();
  if (m.eta1 > 0.0) tau_min = std::min(tau_min, m.eta1 / m.E1);  // free recovery
  for (const MaxwellArm& a : maxwell_arms(m)) tau_min = std::min(tau_min, a.tau_s);
  if (m.lag_s > 0.0) tau_min = std::min(tau_min, m.lag_s);
  const double dt_max = std::max(kMinStepS, std::min(kMaxStepS, tau_min / 20.0));
  const double sample_dt = 1.0 / rate_hz;
  const double n_sub = std::max(1.0, std::ceil(sample_dt / dt_max - 1e-9));
  return sample_dt / n_sub;
}

ContinuumRecord run_continuum(const ContinuumBody& body, const PlateProtocol& p, double noise_N,
                              std::uint32_t seed) {
  validate(body, p, noise_N);
  const double t_push = p.depth_mm / p.push_mm_s, t_hold = t_push + p.hold_s;
  const double t_rel = t_hold + p.depth_mm / p.release_mm_s, t_end = t_rel + p.after_s;
  auto plate_mm = [&](double t) {
    if (t < t_push) return p.push_mm_s * t;
    if (t < t_hold) return p.depth_mm;
    if (t < t_rel) return p.depth_mm - p.release_mm_s * (t - t_hold);
    return 0.0;
  };
  const double sample_dt = 1.0 / p.rate_hz;
  const double dt = continuum_step_s(body.m, p.rate_hz);
  const long n_sub = std::lround(sample_dt / dt);
  const long n_samples = static_cast<long>(std::floor(t_end * p.rate_hz + 1e-9)) + 1;

  Body solid(body, dt);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_N > 0.0 ? noise_N : 1.0);
  const double lag_keep = body.m.lag_s > 0.0 ? std::exp(-dt / body.m.lag_s) : 0.0;
  double force = 0.0, reading = 0.0;
  ContinuumRecord r;
  auto sample = [&](double t) {
    r.t.push_back(t);
    r.plate_mm.push_back(plate_mm(t));
    r.force_N.push_back(reading + body.m.offset_N + (noise_N > 0.0 ? noise(rng) : 0.0));
    r.surface_mm.push_back(solid.surface_m() * 1e3);
  };
  sample(0.0);
  for (long s = 1; s < n_samples; ++s) {
    for (long k = 1; k <= n_sub; ++k) {
      // Times from integers so that the step grid cannot drift from the sample grid.
      const double t = ((s - 1) * n_sub + k) * dt;
      force = solid.step(plate_mm(t) * 1e-3, t);
      reading = lag_keep * reading + (1.0 - lag_keep) * force;
    }
    sample(s * sample_dt);
  }
  return r;
}

void write_measurement_csv(const std::string& path, const ContinuumBody& body,
                           const ContinuumRecord& r, bool with_surface, const std::string& note) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out.precision(10);
  out << "# rheo-measurement: 1\n# specimen_height_mm: " << body.height_mm
      << "\n# specimen_width_mm: " << body.width_mm << "\n# specimen_depth_mm: " << body.depth_mm
      << "\n# SYNTHETIC: " << note << "\ntime_s,plate_mm,force_N,surface_mm\n";
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    out << r.t[i] << ',' << r.plate_mm[i] << ',' << r.force_N[i] << ',';
    if (with_surface) out << r.surface_mm[i];
    out << '\n';
  }
}

}  // namespace rheo::testing
