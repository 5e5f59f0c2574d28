// Element matrices of linear simplices (constant-strain triangles and tetrahedra) and the
// global stiffness of a unit Young's modulus. Internal to the continuum model (fe/solver.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "fe/law.hpp"
#include "fe/mesh.hpp"

namespace rheo::fe {

// One element: its strain-displacement matrix (Voigt strain, engineering shears, over the
// element's dim (dim + 1) nodal displacements in node order) and its measure: area times
// thickness in 2-D, volume in 3-D [m^2 m or m^3].
struct ElementGeometry {
  Eigen::MatrixXd B;
  double measure = 0.0;
};

int voigt_size(int dim);

// Throws rheo::Error when an element's rest measure is not positive (index and value named),
// or when the thickness is not positive and finite in 2-D.
std::vector<ElementGeometry> element_geometry(const Mesh& mesh, double thickness_m);

// Global dof of node a's component c: dim a + c.
inline int dof(int dim, int node, int component) { return dim * node + component; }

// sum_e measure_e B_e^T C B_e, over all dofs.
Eigen::SparseMatrix<double> assemble_stiffness(const Mesh& mesh,
                                               const std::vector<ElementGeometry>& geometry,
                                               const Eigen::MatrixXd& C);

// The element's nodal displacements gathered from the global vector.
Eigen::VectorXd gather(const Mesh& mesh, int element, const Eigen::VectorXd& u);

// global += values over the element's dofs.
void scatter_add(const Mesh& mesh, int element, const Eigen::VectorXd& values,
                 Eigen::VectorXd& global);

}  // namespace rheo::fe
