#include "fe/assembly.hpp"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

#include "sim/error.hpp"

namespace rheo::fe {

int voigt_size(int dim) { return dim == 2 ? 3 : 6; }

std::vector<ElementGeometry> element_geometry(const Mesh& mesh, double thickness_m) {
  const int d = mesh.dim;
  if (d != 2 && d != 3) throw Error("mesh dim = " + std::to_string(d) + ": expected 2 or 3");
  if (d == 2 && (!std::isfinite(thickness_m) || !(thickness_m > 0.0))) {
    std::ostringstream os;
    os << "thickness = " << thickness_m << " m: expected positive and finite";
    throw Error(os.str());
  }
  const int n = d + 1;
  std::vector<ElementGeometry> out(mesh.elements.size());
  for (int e = 0; e < mesh.element_count(); ++e) {
    const auto& nodes = mesh.elements[e];
    for (int a = 0; a < n; ++a) {
      if (nodes[a] < 0 || nodes[a] >= mesh.node_count()) {
        std::ostringstream os;
        os << "mesh element " << e << " names node " << nodes[a] << ": expected 0 to "
           << mesh.node_count() - 1;
        throw Error(os.str());
      }
    }
    const double measure = signed_measure(mesh, e);
    if (!std::isfinite(measure) || !(measure > 0.0)) {
      std::ostringstream os;
      os << "mesh element " << e << " has rest " << (d == 2 ? "area " : "volume ") << measure
         << ": expected positive (nodes counter-clockwise / positively oriented)";
      throw Error(os.str());
    }
    // J = [x_1 - x_0, ..., x_d - x_0]; the gradients of N_1..N_d are the rows of J^-1.
    Eigen::MatrixXd J(d, d);
    for (int a = 1; a < n; ++a) J.col(a - 1) = mesh.nodes.col(nodes[a]) - mesh.nodes.col(nodes[0]);
    const Eigen::MatrixXd Jinv = J.inverse();
    Eigen::MatrixXd grad(n, d);  // row a: grad N_a
    grad.bottomRows(d) = Jinv;
    grad.row(0) = -Jinv.colwise().sum();
    ElementGeometry& g = out[e];
    g.measure = d == 2 ? measure * thickness_m : measure;
    g.B = Eigen::MatrixXd::Zero(voigt_size(d), d * n);
    for (int a = 0; a < n; ++a) {
      if (d == 2) {  // (xx, zz, xz) over (u_x, u_z)
        const double gx = grad(a, 0), gz = grad(a, 1);
        g.B(0, 2 * a) = gx;
        g.B(1, 2 * a + 1) = gz;
        g.B(2, 2 * a) = gz;
        g.B(2, 2 * a + 1) = gx;
      } else {  // (xx, yy, zz, yz, xz, xy)
        const double gx = grad(a, 0), gy = grad(a, 1), gz = grad(a, 2);
        const int c = 3 * a;
        g.B(0, c) = gx;
        g.B(1, c + 1) = gy;
        g.B(2, c + 2) = gz;
        g.B(3, c + 1) = gz;
        g.B(3, c + 2) = gy;
        g.B(4, c) = gz;
        g.B(4, c + 2) = gx;
        g.B(5, c) = gy;
        g.B(5, c + 1) = gx;
      }
    }
  }
  return out;
}

Eigen::SparseMatrix<double> assemble_stiffness(const Mesh& mesh,
                                               const std::vector<ElementGeometry>& geometry,
                                               const Eigen::MatrixXd& C) {
  const int d = mesh.dim, n = d + 1, m = d * n;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(geometry.size() * static_cast<std::size_t>(m * m));
  for (int e = 0; e < mesh.element_count(); ++e) {
    const ElementGeometry& g = geometry[e];
    const Eigen::MatrixXd k = g.measure * g.B.transpose() * C * g.B;
    for (int a = 0; a < n; ++a) {
      for (int ca = 0; ca < d; ++ca) {
        for (int b = 0; b < n; ++b) {
          for (int cb = 0; cb < d; ++cb) {
            triplets.emplace_back(dof(d, mesh.elements[e][a], ca), dof(d, mesh.elements[e][b], cb),
                                  k(d * a + ca, d * b + cb));
          }
        }
      }
    }
  }
  const int ndof = d * mesh.node_count();
  Eigen::SparseMatrix<double> K(ndof, ndof);
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

Eigen::VectorXd gather(const Mesh& mesh, int element, const Eigen::VectorXd& u) {
  const int d = mesh.dim, n = d + 1;
  Eigen::VectorXd ue(d * n);
  for (int a = 0; a < n; ++a) {
    for (int c = 0; c < d; ++c) ue[d * a + c] = u[dof(d, mesh.elements[element][a], c)];
  }
  return ue;
}

void scatter_add(const Mesh& mesh, int element, const Eigen::VectorXd& values,
                 Eigen::VectorXd& global) {
  const int d = mesh.dim, n = d + 1;
  for (int a = 0; a < n; ++a) {
    for (int c = 0; c < d; ++c) global[dof(d, mesh.elements[element][a], c)] += values[d * a + c];
  }
}

}  // namespace rheo::fe
