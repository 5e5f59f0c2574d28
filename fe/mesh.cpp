#include "fe/mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "sim/error.hpp"

namespace rheo::fe {

namespace {

void check_size(const char* what, double v) {
  if (!std::isfinite(v) || !(v > 0.0)) {
    std::ostringstream os;
    os << "mesh " << what << " = " << v << " m: expected positive and finite";
    throw Error(os.str());
  }
}

void check_cells(const char* what, int n) {
  if (n < 1) {
    std::ostringstream os;
    os << "mesh " << what << " = " << n << ": expected at least 1 cell";
    throw Error(os.str());
  }
}

// Coordinate i of n cells over length L, exactly L at i = n.
double grid(double L, int i, int n) { return i == n ? L : L * i / n; }

// Swaps two nodes of an element whose rest measure is negative.
void orient(Mesh& mesh, int e) {
  if (signed_measure(mesh, e) < 0.0) std::swap(mesh.elements[e][0], mesh.elements[e][1]);
}

}  // namespace

Mesh make_rectangle(double width_m, double height_m, int nx, int nz, TriangleSplit split) {
  check_size("width", width_m);
  check_size("height", height_m);
  check_cells("nx", nx);
  check_cells("nz", nz);
  Mesh m;
  m.dim = 2;
  m.height_m = height_m;
  const auto id = [nx](int i, int k) { return k * (nx + 1) + i; };
  m.nodes.resize(2, (nx + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k) {
    for (int i = 0; i <= nx; ++i) {
      m.nodes(0, id(i, k)) = grid(width_m, i, nx);
      m.nodes(1, id(i, k)) = grid(height_m, k, nz);
    }
  }
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, k), b = id(i + 1, k), c = id(i + 1, k + 1), d = id(i, k + 1);
      const bool rising = split == TriangleSplit::kUniform || (i + k) % 2 == 0;
      if (rising) {  // diagonal a-c
        m.elements.push_back({a, b, c, -1});
        m.elements.push_back({a, c, d, -1});
      } else {  // diagonal b-d
        m.elements.push_back({a, b, d, -1});
        m.elements.push_back({b, c, d, -1});
      }
    }
  }
  for (int i = 0; i <= nx; ++i) {
    m.bottom_nodes.push_back(id(i, 0));
    m.top_nodes.push_back(id(i, nz));
  }
  for (int e = 0; e < m.element_count(); ++e) orient(m, e);
  return m;
}

Mesh make_box(double width_m, double depth_m, double height_m, int nx, int ny, int nz,
              TetSplit split) {
  check_size("width", width_m);
  check_size("depth", depth_m);
  check_size("height", height_m);
  check_cells("nx", nx);
  check_cells("ny", ny);
  check_cells("nz", nz);
  Mesh m;
  m.dim = 3;
  m.height_m = height_m;
  const auto id = [nx, ny](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  m.nodes.resize(3, (nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        m.nodes(0, id(i, j, k)) = grid(width_m, i, nx);
        m.nodes(1, id(i, j, k)) = grid(depth_m, j, ny);
        m.nodes(2, id(i, j, k)) = grid(height_m, k, nz);
      }
    }
  }
  // Cell corner v = a + 2 b + 4 c for the offsets (a, b, c) in x, y, z.
  using Tet = std::array<int, 4>;
  // Kuhn: the paths 0 -> 7 along the three axes in every order.
  static const std::array<Tet, 6> kSix = {{{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                           {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};
  // Five: in an even cell the central tetrahedron joins the corners of odd offset sum (1, 2,
  // 4, 7); in an odd cell those of even sum (0, 3, 5, 6). Every face diagonal then joins two
  // nodes of odd i + j + k, in both kinds of cell.
  static const std::array<Tet, 5> kFiveEven = {
      {{1, 2, 4, 7}, {0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}}};
  static const std::array<Tet, 5> kFiveOdd = {
      {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 3, 6}, {4, 0, 5, 6}, {7, 3, 5, 6}}};
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        std::array<int, 8> corner;
        for (int v = 0; v < 8; ++v) corner[v] = id(i + (v & 1), j + ((v >> 1) & 1), k + (v >> 2));
        const auto add = [&](const Tet& t) {
          m.elements.push_back({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
        };
        if (split == TetSplit::kSix) {
          for (const Tet& t : kSix) add(t);
        } else {
          for (const Tet& t : ((i + j + k) % 2 == 0 ? kFiveEven : kFiveOdd)) add(t);
        }
      }
    }
  }
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      m.bottom_nodes.push_back(id(i, j, 0));
      m.top_nodes.push_back(id(i, j, nz));
    }
  }
  for (int e = 0; e < m.element_count(); ++e) orient(m, e);
  return m;
}

double signed_measure(const Mesh& mesh, int element, const Eigen::VectorXd* displacement) {
  const std::array<int, 4>& n = mesh.elements.at(static_cast<std::size_t>(element));
  const int d = mesh.dim;
  const auto at = [&](int a) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int c = 0; c < d; ++c) {
      x[c] = mesh.nodes(c, n[a]);
      if (displacement != nullptr) x[c] += (*displacement)[d * n[a] + c];
    }
    return x;
  };
  const Eigen::Vector3d x0 = at(0);
  const Eigen::Vector3d e1 = at(1) - x0, e2 = at(2) - x0;
  if (d == 2) return 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]);
  const Eigen::Vector3d e3 = at(3) - x0;
  return e1.dot(e2.cross(e3)) / 6.0;
}

}  // namespace rheo::fe
