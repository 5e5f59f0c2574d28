// Structured simplex meshes of the continuum model: a rectangle of linear triangles in the
// x-z plane (z up) and a box of linear tetrahedra (x, y, z; z up). Every element's nodes are
// ordered so that its signed area / volume at rest is positive.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace rheo::fe {

// How each rectangular cell is cut into two triangles: all along the same diagonal (uniform,
// which gives the mesh a directional bias), or along alternating diagonals in a checkerboard
// (crossed), which makes the mesh symmetric about the rectangle's centre lines for even nx, nz.
enum class TriangleSplit { kUniform, kAlternating };

// How each hexahedral cell is cut: six tetrahedra around the cell's main diagonal (Kuhn; every
// cell alike) or five (a central tetrahedron and four corners, mirrored in alternate cells).
// Both give conforming meshes: neighbouring cells cut a shared face along the same diagonal.
enum class TetSplit { kFive, kSix };

struct Mesh {
  int dim = 2;                               // 2: nodes (x, z); 3: nodes (x, y, z)
  Eigen::MatrixXd nodes;                     // dim x node count, rest positions [m]
  std::vector<std::array<int, 4>> elements;  // dim + 1 nodes each (2-D: [3] = -1)
  std::vector<int> bottom_nodes;             // on z = 0
  std::vector<int> top_nodes;                // on z = height, ordered by x (3-D: y, then x)
  double height_m = 0.0;

  int node_count() const { return static_cast<int>(nodes.cols()); }
  int element_count() const { return static_cast<int>(elements.size()); }
  int nodes_per_element() const { return dim + 1; }
};

// width x height [m] in nx x nz cells, 2 nx nz triangles. Throws rheo::Error naming a size
// that is not positive and finite, or a cell count < 1.
Mesh make_rectangle(double width_m, double height_m, int nx, int nz,
                    TriangleSplit split = TriangleSplit::kAlternating);

// width (x) x depth (y) x height (z) [m] in nx x ny x nz cells of 5 or 6 tetrahedra.
Mesh make_box(double width_m, double depth_m, double height_m, int nx, int ny, int nz,
              TetSplit split = TetSplit::kSix);

// Signed area (2-D) or volume (3-D) of an element, at rest or displaced by `displacement`
// (dim values per node). Positive at rest for every element of the meshes above.
double signed_measure(const Mesh& mesh, int element,
                      const Eigen::VectorXd* displacement = nullptr);

}  // namespace rheo::fe
