#include "fe/solver.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "fe/assembly.hpp"
#include "sim/error.hpp"

namespace rheo::fe {

struct ContinuumModel::Impl {
  Mesh mesh;
  ViscoelasticLaw law;
  ModelOptions opt;
  int d = 2, ndof = 0, nv = 3, ne = 0;
  std::vector<ElementGeometry> geo;
  Eigen::MatrixXd C1;              // unit elasticity
  Eigen::SparseMatrix<double> K1;  // stiffness of E = 1
  std::vector<char> floor_fixed;   // per dof

  // State at the end of the last step.
  double t = 0.0, depth = 0.0, force = 0.0;
  Eigen::VectorXd u, r;
  Eigen::MatrixXd eps;             // nv x ne, element strains
  std::vector<Eigen::MatrixXd> q;  // per arm, nv x ne
  std::vector<char> contact;       // per top node
  Eigen::MatrixXd stick;           // (d - 1) x top nodes: held horizontal displacement

  // The factorisation of the free-free block and what it was made for.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  bool factored = false;
  double factor_dt = 0.0;
  std::vector<char> factor_mask;
  std::vector<int> free_index;  // dof -> row of the reduced system, -1 if prescribed
  int free_count = 0;
  int factorisations = 0;

  void factorise(double dt, double modulus, const std::vector<char>& mask, double t_end);
  StepReport step(double dt, double plate_depth);
};

namespace {

std::string at_time(double t) {
  std::ostringstream os;
  os << " at t = " << t << " s";
  return os.str();
}

}  // namespace

void ContinuumModel::Impl::factorise(double dt, double modulus, const std::vector<char>& mask,
                                     double t_end) {
  free_index.assign(ndof, -1);
  free_count = 0;
  for (int i = 0; i < ndof; ++i) {
    if (!mask[i]) free_index[i] = free_count++;
  }
  factored = true;
  factor_dt = dt;
  factor_mask = mask;
  if (free_count == 0) return;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(K1.nonZeros());
  for (int col = 0; col < K1.outerSize(); ++col) {
    if (free_index[col] < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(K1, col); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (free_index[row] >= 0) triplets.emplace_back(free_index[row], free_index[col], modulus * it.value());
    }
  }
  Eigen::SparseMatrix<double> K(free_count, free_count);
  K.setFromTriplets(triplets.begin(), triplets.end());
  ldlt.compute(K);
  ++factorisations;
  bool ok = ldlt.info() == Eigen::Success;
  if (ok) {
    // A stiffness with a rigid motion left free has a (rounding-level) zero pivot.
    const Eigen::VectorXd D = ldlt.vectorD();
    ok = D.allFinite() && D.minCoeff() > 1e-13 * D.cwiseAbs().maxCoeff();
  }
  if (!ok) {
    factored = false;
    throw Error("stiffness factorisation failed" + at_time(t_end) +
                ": the constraints leave a rigid motion free or the matrix is not positive"
                " definite (effective modulus " + std::to_string(modulus) + " Pa)");
  }
}

StepReport ContinuumModel::Impl::step(double dt, double plate_depth) {
  const StepFactors f = law.step_factors(dt);
  const double t_end = t + dt;
  if (!std::isfinite(plate_depth)) {
    throw Error("plate depth = " + std::to_string(plate_depth) + " m" + at_time(t_end) +
                ": expected finite");
  }
  // History part of every element's stress (per unit C1) and its nodal forces:
  // sigma(n+1) = C1 (E_eff eps(n+1) + h),  h = sum_k e_k (a_k q_k - b_k eps(n)) - eta/dt eps(n).
  Eigen::MatrixXd h = -f.viscous * eps;
  const auto& arms = law.arms();
  for (std::size_t k = 0; k < arms.size(); ++k) {
    h += arms[k].modulus_Pa * (f.decay[k] * q[k] - f.gain[k] * eps);
  }
  Eigen::VectorXd f_hist = Eigen::VectorXd::Zero(ndof);
  for (int e = 0; e < ne; ++e) {
    const Eigen::VectorXd fe = geo[e].measure * (geo[e].B.transpose() * (C1 * h.col(e)));
    scatter_add(mesh, e, fe, f_hist);
  }

  const int ntop = static_cast<int>(mesh.top_nodes.size());
  const int vert = d - 1;
  const double plate_z = mesh.height_m - plate_depth;
  const double gap_tol = 1e-12 * mesh.height_m;
  std::vector<char> active = contact;
  Eigen::MatrixXd held = stick;
  Eigen::VectorXd un(ndof), rn(ndof);
  int iterations = 0, factorisations_before = factorisations;
  for (;;) {
    if (iterations >= opt.max_contact_iterations) {
      std::ostringstream os;
      os << "plate contact: the active set did not settle in max_contact_iterations = "
         << opt.max_contact_iterations << " iterations" << at_time(t_end)
         << " (plate depth " << plate_depth << " m); expected a larger cap or a smaller step";
      throw Error(os.str());
    }
    ++iterations;
    std::vector<char> mask = floor_fixed;
    Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(ndof);
    for (int i = 0; i < ntop; ++i) {
      if (!active[i]) continue;
      const int node = mesh.top_nodes[i];
      mask[dof(d, node, vert)] = 1;
      prescribed[dof(d, node, vert)] = plate_z - mesh.nodes(vert, node);
      if (opt.contact == PlateContact::kBonded) {
        for (int c = 0; c < vert; ++c) {
          mask[dof(d, node, c)] = 1;
          prescribed[dof(d, node, c)] = held(c, i);
        }
      }
    }
    if (!factored || factor_dt != dt || factor_mask != mask) {
      factorise(dt, f.effective_modulus, mask, t_end);
    }
    const Eigen::VectorXd known = f.effective_modulus * (K1 * prescribed) + f_hist;
    un = prescribed;
    if (free_count > 0) {
      Eigen::VectorXd rhs(free_count);
      for (int i = 0; i < ndof; ++i) {
        if (free_index[i] >= 0) rhs[free_index[i]] = -known[i];
      }
      const Eigen::VectorXd x = ldlt.solve(rhs);
      if (ldlt.info() != Eigen::Success || !x.allFinite()) {
        throw Error("linear solve failed or gave non-finite displacements" + at_time(t_end));
      }
      for (int i = 0; i < ndof; ++i) {
        if (free_index[i] >= 0) un[i] = x[free_index[i]];
      }
    }
    rn = f.effective_modulus * (K1 * un) + f_hist;
    if (!rn.allFinite()) throw Error("non-finite nodal forces" + at_time(t_end));
    double scale = 0.0;
    for (int i = 0; i < ndof; ++i) {
      if (mask[i]) scale = std::max(scale, std::abs(rn[i]));
    }
    const double force_tol = 1e-9 * scale;
    bool changed = false;
    for (int i = 0; i < ntop; ++i) {
      const int node = mesh.top_nodes[i];
      if (active[i]) {
        // The plate pushes the node with -r_z (downward positive); a pull releases it.
        if (-rn[dof(d, node, vert)] < -force_tol) {
          active[i] = 0;
          changed = true;
        }
      } else if (mesh.nodes(vert, node) + un[dof(d, node, vert)] > plate_z + gap_tol) {
        active[i] = 1;
        for (int c = 0; c < vert; ++c) held(c, i) = u[dof(d, node, c)];
        changed = true;
      }
    }
    if (!changed) break;
  }

  for (int e = 0; e < ne; ++e) {
    const double m = signed_measure(mesh, e, &un);
    if (!std::isfinite(m) || !(m > 0.0)) {
      std::ostringstream os;
      os << "element " << e << " inverted" << at_time(t_end) << ": deformed "
         << (d == 2 ? "area " : "volume ") << m << ", rest " << signed_measure(mesh, e)
         << " (expected the rest sign; the strain is far beyond the small-strain model)";
      throw Error(os.str());
    }
  }
  double force = 0.0;
  int in_contact = 0;
  for (int i = 0; i < ntop; ++i) {
    if (active[i]) {
      force -= rn[dof(d, mesh.top_nodes[i], vert)];
      ++in_contact;
    }
  }
  if (!std::isfinite(force)) throw Error("non-finite plate force" + at_time(t_end));

  // Commit: strains and the arms' exact update q <- a q + b (eps(n+1) - eps(n)).
  for (int e = 0; e < ne; ++e) {
    const Eigen::VectorXd e_new = geo[e].B * gather(mesh, e, un);
    const Eigen::VectorXd de = e_new - eps.col(e);
    for (std::size_t k = 0; k < arms.size(); ++k) {
      q[k].col(e) = f.decay[k] * q[k].col(e) + f.gain[k] * de;
    }
    eps.col(e) = e_new;
  }
  u = un;
  r = rn;
  t = t_end;
  depth = plate_depth;
  this->force = force;
  contact = active;
  stick = held;

  StepReport rep;
  rep.t_s = t;
  rep.plate_depth_m = depth;
  rep.force_N = force;
  rep.contact_iterations = iterations;
  rep.contact_nodes = in_contact;
  rep.factorisations = factorisations - factorisations_before;
  return rep;
}

ContinuumModel::ContinuumModel(Mesh mesh, ViscoelasticLaw law, ModelOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const bool solid = options.formulation == Formulation::kSolid;
  if (mesh.dim != (solid ? 3 : 2)) {
    std::ostringstream os;
    os << "mesh dim = " << mesh.dim << ": expected " << (solid ? 3 : 2) << " for "
       << to_string(options.formulation);
    throw Error(os.str());
  }
  if (mesh.element_count() == 0 || mesh.top_nodes.empty() || mesh.bottom_nodes.empty()) {
    throw Error("mesh: expected elements, top nodes and bottom nodes (got " +
                std::to_string(mesh.element_count()) + " elements)");
  }
  if (!std::isfinite(mesh.height_m) || !(mesh.height_m > 0.0)) {
    throw Error("mesh height = " + std::to_string(mesh.height_m) + " m: expected positive");
  }
  if (options.max_contact_iterations < 1) {
    throw Error("max_contact_iterations = " + std::to_string(options.max_contact_iterations) +
                ": expected at least 1");
  }
  check_poisson(law.poisson(), options.formulation);
  m.d = mesh.dim;
  m.nv = voigt_size(m.d);
  m.ne = mesh.element_count();
  m.ndof = m.d * mesh.node_count();
  m.geo = element_geometry(mesh, options.thickness_m);
  m.C1 = unit_elasticity(law.poisson(), options.formulation);
  m.K1 = assemble_stiffness(mesh, m.geo, m.C1);

  m.floor_fixed.assign(m.ndof, 0);
  const int vert = m.d - 1;
  for (int node : mesh.bottom_nodes) {
    if (options.floor == FloorCondition::kBonded) {
      for (int c = 0; c < m.d; ++c) m.floor_fixed[dof(m.d, node, c)] = 1;
    } else {
      m.floor_fixed[dof(m.d, node, vert)] = 1;
    }
  }
  if (options.floor == FloorCondition::kSliding) {
    // The bottom node of least x (then y), and in 3-D the one of greatest x among those of
    // least y: all horizontal components at the first, y at the second.
    const auto key = [&](int node, int c) { return mesh.nodes(c, node); };
    int origin = mesh.bottom_nodes.front();
    for (int node : mesh.bottom_nodes) {
      const bool less = m.d == 2 ? key(node, 0) < key(origin, 0)
                                 : std::make_pair(key(node, 1), key(node, 0)) <
                                       std::make_pair(key(origin, 1), key(origin, 0));
      if (less) origin = node;
    }
    for (int c = 0; c < vert; ++c) m.floor_fixed[dof(m.d, origin, c)] = 1;
    if (m.d == 3) {
      int far = origin;
      for (int node : mesh.bottom_nodes) {
        if (key(node, 1) == key(origin, 1) && key(node, 0) > key(far, 0)) far = node;
      }
      if (far == origin) throw Error("sliding floor: the mesh has one bottom node on its edge y = min");
      m.floor_fixed[dof(m.d, far, 1)] = 1;
    }
  }

  m.u = Eigen::VectorXd::Zero(m.ndof);
  m.r = Eigen::VectorXd::Zero(m.ndof);
  m.eps = Eigen::MatrixXd::Zero(m.nv, m.ne);
  m.q.assign(law.arms().size(), Eigen::MatrixXd::Zero(m.nv, m.ne));
  m.contact.assign(mesh.top_nodes.size(), 0);
  m.stick = Eigen::MatrixXd::Zero(m.d - 1, static_cast<Eigen::Index>(mesh.top_nodes.size()));
  m.mesh = std::move(mesh);
  m.law = std::move(law);
  m.opt = options;
}

ContinuumModel::~ContinuumModel() = default;
ContinuumModel::ContinuumModel(ContinuumModel&&) noexcept = default;
ContinuumModel& ContinuumModel::operator=(ContinuumModel&&) noexcept = default;

StepReport ContinuumModel::step(double dt_s, double plate_depth_m) {
  return impl_->step(dt_s, plate_depth_m);
}

double ContinuumModel::time_s() const { return impl_->t; }
double ContinuumModel::plate_depth_m() const { return impl_->depth; }
double ContinuumModel::plate_force_N() const { return impl_->force; }
const Eigen::VectorXd& ContinuumModel::displacement() const { return impl_->u; }
const Eigen::VectorXd& ContinuumModel::nodal_forces() const { return impl_->r; }
int ContinuumModel::factorisations() const { return impl_->factorisations; }
const Mesh& ContinuumModel::mesh() const { return impl_->mesh; }
const ViscoelasticLaw& ContinuumModel::law() const { return impl_->law; }
const ModelOptions& ContinuumModel::options() const { return impl_->opt; }

std::vector<double> ContinuumModel::top_vertical_displacement() const {
  const Impl& m = *impl_;
  std::vector<double> out;
  for (int node : m.mesh.top_nodes) out.push_back(m.u[dof(m.d, node, m.d - 1)]);
  return out;
}

std::vector<bool> ContinuumModel::top_in_contact() const {
  return std::vector<bool>(impl_->contact.begin(), impl_->contact.end());
}

}  // namespace rheo::fe
