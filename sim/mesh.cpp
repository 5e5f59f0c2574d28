#include "sim/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "sim/error.hpp"

namespace rheo {

namespace {

void check_spec(const BlockSpec& spec) {
  auto fail = [](const std::string& field, double value, const char* expected) {
    throw Error("invalid block: " + field + " = " + std::to_string(value) + ", expected " +
                expected);
  };
  if (spec.dim != 2 && spec.dim != 3) fail("dim", spec.dim, "2 or 3");
  if (spec.nx < 2) fail("nx", spec.nx, "at least 2 particles");
  if (spec.dim == 3 && spec.ny < 2) fail("ny", spec.ny, "at least 2 particles");
  if (spec.nz < 2) fail("nz", spec.nz, "at least 2 particles");
  auto positive = [&](const char* field, double v) {
    if (!std::isfinite(v) || v <= 0.0) fail(field, v, "a finite value > 0");
  };
  positive("sx", spec.sx);
  positive("sy", spec.sy);
  positive("sz", spec.sz);
  positive("density", spec.density);
  positive("mass_scale", spec.mass_scale);
}

// Collects undirected particle pairs; edges run from the lower to the higher index so
// that the edge list comes out sorted by start particle (good locality in the loop).
class EdgeSet {
 public:
  void add(int a, int b) { pairs_.insert(std::minmax(a, b)); }
  const std::set<std::pair<int, int>>& pairs() const { return pairs_; }

 private:
  std::set<std::pair<int, int>> pairs_;
};

// Kuhn (Freudenthal) split of a cube into 6 tetrahedra around its main diagonal
// corner 0 -> corner 7. Corner c has offsets (c & 1, (c >> 1) & 1, (c >> 2) & 1). Every
// face gets the diagonal through its lowest and highest corner, so neighbouring cells
// split their shared faces the same way and the mesh is conforming.
constexpr int kKuhnTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                 {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

}  // namespace

Model make_block(const BlockSpec& spec) {
  check_spec(spec);
  Model model;
  model.dim = spec.dim;
  const bool three_d = spec.dim == 3;
  const int nx = spec.nx;
  const int ny = three_d ? spec.ny : 1;
  const int nz = spec.nz;
  const double hx = spec.sx / (nx - 1);
  const double hy = three_d ? spec.sy / (ny - 1) : 0.0;
  const double hz = spec.sz / (nz - 1);
  auto index = [&](int i, int j, int k) { return i + nx * (j + ny * k); };

  const int n = nx * ny * nz;
  model.x0.resize(n);
  model.flags.assign(n, kFree);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const int p = index(i, j, k);
        model.x0[p] = Vec3(i * hx, j * hy, k * hz);
        if (k == 0 && spec.fix_bottom) model.flags[p] = kFixed;
        if (k == nz - 1 && spec.plate_top) model.flags[p] = kPlate;
      }
    }
  }

  EdgeSet edges;
  if (!three_d) {
    for (int k = 0; k + 1 < nz; ++k) {
      for (int i = 0; i + 1 < nx; ++i) {
        const int a = index(i, 0, k), b = index(i + 1, 0, k);
        const int c = index(i, 0, k + 1), d = index(i + 1, 0, k + 1);
        // Alternating diagonals keep the truss free of a preferred shear direction.
        if ((i + k) % 2 == 0) {
          model.triangles.push_back({a, b, d});
          model.triangles.push_back({a, d, c});
        } else {
          model.triangles.push_back({a, b, c});
          model.triangles.push_back({b, d, c});
        }
        edges.add(a, b);
        edges.add(c, d);
        edges.add(a, c);
        edges.add(b, d);
        if (spec.structure == Structure::kLattice || (i + k) % 2 == 0) edges.add(a, d);
        if (spec.structure == Structure::kLattice || (i + k) % 2 == 1) edges.add(b, c);
      }
    }
  } else {
    for (int k = 0; k + 1 < nz; ++k) {
      for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i + 1 < nx; ++i) {
          int corner[8];
          for (int c = 0; c < 8; ++c) {
            corner[c] = index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          }
          for (const auto& tet : kKuhnTets) {
            model.tetrahedra.push_back(
                {corner[tet[0]], corner[tet[1]], corner[tet[2]], corner[tet[3]]});
            if (spec.structure == Structure::kTruss) {
              for (int a = 0; a < 4; ++a) {
                for (int b = a + 1; b < 4; ++b) edges.add(corner[tet[a]], corner[tet[b]]);
              }
            }
          }
          if (spec.structure == Structure::kLattice) {
            // All 28 corner pairs: 12 axis edges, 12 face diagonals, 4 body diagonals.
            for (int a = 0; a < 8; ++a) {
              for (int b = a + 1; b < 8; ++b) edges.add(corner[a], corner[b]);
            }
          }
        }
      }
    }
  }

  double sum_l2 = 0.0;
  model.edges.reserve(edges.pairs().size());
  for (const auto& [s, e] : edges.pairs()) {
    const double l = (model.x0[e] - model.x0[s]).norm();
    model.edges.push_back(Edge{s, e, l, l, 0});
    sum_l2 += l * l;
  }

  // Affine (Cauchy-Born) central-force network: under a uniform strain every edge
  // stretches affinely, and matching the network's energy to the continuum's gives one
  // factor per unit modulus for all edges (see mesh.hpp).
  const double volume = spec.sx * spec.sy * spec.sz;  // 2D: area sx*sz times depth sy
  const double per_modulus = (three_d ? 6.0 : 3.0) * volume / sum_l2;
  const double top_area = spec.sx * spec.sy;
  const int top_particles = nx * ny;
  const double per_stress = top_area / top_particles;
  EdgeMaterial m = spec.material;
  m.k1 *= per_modulus;
  m.c1 *= per_modulus;
  m.c2 *= per_modulus;
  m.c2_min *= per_modulus;
  m.k2 *= per_modulus;
  m.c3 *= per_modulus;
  for (int j = 0; j < m.spectrum_arms; ++j) {
    m.spectrum[j].k *= per_modulus;
    m.spectrum[j].c *= per_modulus;
  }
  m.f1 *= per_stress;
  m.f2 *= per_stress;
  model.materials.push_back(m);

  const double particle_mass = spec.density * volume / n * spec.mass_scale;
  model.mass.assign(n, particle_mass);
  model.topology = spec.topology;
  model.volume = spec.volume;
  model.mass_scale = spec.mass_scale;
  model.size = std::max({spec.sx, three_d ? spec.sy : 0.0, spec.sz});
  model.height = spec.sz;
  model.top_area = top_area;
  return model;
}

}  // namespace rheo
