// Structured meshes: counts, areas/volumes, orientation and conformity (every interior edge or
// face shared by exactly two elements, every boundary one by one).
#include "fe/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "sim/error.hpp"

namespace rheo::fe {
namespace {

// Facets (edges in 2-D, faces in 3-D) as sorted node lists, with their number of elements.
std::map<std::vector<int>, int> facets(const Mesh& m) {
  std::map<std::vector<int>, int> count;
  const int n = m.nodes_per_element();
  for (const auto& el : m.elements) {
    for (int skip = 0; skip < n; ++skip) {
      std::vector<int> f;
      for (int a = 0; a < n; ++a) {
        if (a != skip) f.push_back(el[a]);
      }
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  }
  return count;
}

// On the boundary of the box [0, size] when all its nodes share one extreme coordinate.
bool on_boundary(const Mesh& m, const std::vector<int>& f, const std::vector<double>& size) {
  for (int c = 0; c < m.dim; ++c) {
    for (double v : {0.0, size[c]}) {
      if (std::all_of(f.begin(), f.end(), [&](int i) { return m.nodes(c, i) == v; })) return true;
    }
  }
  return false;
}

void expect_conforming(const Mesh& m, const std::vector<double>& size) {
  for (const auto& [f, count] : facets(m)) {
    EXPECT_EQ(count, on_boundary(m, f, size) ? 1 : 2) << "facet of node " << f[0];
  }
}

TEST(FeMesh, RectangleCountsAreaOrientationAndConformity) {
  for (TriangleSplit split : {TriangleSplit::kUniform, TriangleSplit::kAlternating}) {
    for (auto [nx, nz] : std::vector<std::array<int, 2>>{{1, 1}, {4, 4}, {5, 3}, {7, 10}}) {
      const Mesh m = make_rectangle(0.08, 0.05, nx, nz, split);
      EXPECT_EQ(m.node_count(), (nx + 1) * (nz + 1));
      EXPECT_EQ(m.element_count(), 2 * nx * nz);
      EXPECT_EQ(m.top_nodes.size(), static_cast<std::size_t>(nx + 1));
      double area = 0.0;
      for (int e = 0; e < m.element_count(); ++e) {
        EXPECT_GT(signed_measure(m, e), 0.0);
        area += signed_measure(m, e);
      }
      // Sums of nx nz cell areas: rounding only.
      EXPECT_NEAR(area, 0.08 * 0.05, 1e-15);
      expect_conforming(m, {0.08, 0.05});
      for (std::size_t i = 1; i < m.top_nodes.size(); ++i) {
        EXPECT_GT(m.nodes(0, m.top_nodes[i]), m.nodes(0, m.top_nodes[i - 1]));
      }
    }
  }
}

TEST(FeMesh, AlternatingSplitIsMirrorSymmetric) {
  // With even nx the crossed split maps onto itself under x -> width - x: no directional bias.
  const Mesh m = make_rectangle(1.0, 1.0, 4, 4, TriangleSplit::kAlternating);
  std::vector<std::vector<double>> tris, mirrored;
  for (const auto& el : m.elements) {
    std::vector<double> a, b;
    for (int k = 0; k < 3; ++k) {
      a.push_back(m.nodes(0, el[k]) * 10 + m.nodes(1, el[k]));
      b.push_back((1.0 - m.nodes(0, el[k])) * 10 + m.nodes(1, el[k]));
    }
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    tris.push_back(a);
    mirrored.push_back(b);
  }
  std::sort(tris.begin(), tris.end());
  std::sort(mirrored.begin(), mirrored.end());
  EXPECT_EQ(tris, mirrored);
}

TEST(FeMesh, BoxOfFiveOrSixTetsIsConformingAndFillsTheBox) {
  for (TetSplit split : {TetSplit::kFive, TetSplit::kSix}) {
    for (auto [nx, ny, nz] : std::vector<std::array<int, 3>>{{1, 1, 1}, {2, 3, 4}, {3, 3, 3}}) {
      const Mesh m = make_box(0.02, 0.03, 0.01, nx, ny, nz, split);
      EXPECT_EQ(m.node_count(), (nx + 1) * (ny + 1) * (nz + 1));
      EXPECT_EQ(m.element_count(), (split == TetSplit::kFive ? 5 : 6) * nx * ny * nz);
      EXPECT_EQ(m.top_nodes.size(), static_cast<std::size_t>((nx + 1) * (ny + 1)));
      double volume = 0.0;
      for (int e = 0; e < m.element_count(); ++e) {
        EXPECT_GT(signed_measure(m, e), 0.0);
        volume += signed_measure(m, e);
      }
      EXPECT_NEAR(volume, 0.02 * 0.03 * 0.01, 1e-18);
      expect_conforming(m, {0.02, 0.03, 0.01});
    }
  }
}

TEST(FeMesh, DisplacedMeasureSeesAnInvertedElement) {
  const Mesh m = make_rectangle(1.0, 1.0, 1, 1);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * m.node_count());
  for (int node : m.top_nodes) u[2 * node + 1] = -1.5;  // top pushed below the floor
  EXPECT_LT(signed_measure(m, 0, &u), 0.0);
}

TEST(FeMesh, BadSizesAndCountsAreNamed) {
  const auto message = [](auto f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([] { make_rectangle(0.0, 1.0, 2, 2); }).find("width"), std::string::npos);
  EXPECT_NE(message([] { make_rectangle(1.0, -1.0, 2, 2); }).find("height"), std::string::npos);
  EXPECT_NE(message([] { make_rectangle(1.0, 1.0, 0, 2); }).find("nx = 0"), std::string::npos);
  EXPECT_NE(message([] { make_rectangle(1.0, 1.0, 2, 0); }).find("nz = 0"), std::string::npos);
  EXPECT_NE(message([] { make_box(1.0, 1.0, 1.0, 1, 0, 1); }).find("ny = 0"), std::string::npos);
  EXPECT_NE(message([] { make_box(1.0, NAN, 1.0, 1, 1, 1); }).find("depth"), std::string::npos);
}

}  // namespace
}  // namespace rheo::fe
