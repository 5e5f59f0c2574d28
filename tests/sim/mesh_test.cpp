#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>

#include "sim/error.hpp"
#include "sim/mesh.hpp"
#include "sim/simulator.hpp"

namespace rheo {
namespace {

constexpr double kRoundoff = 1e-9;

BlockSpec spec3(Structure structure, int nx, int ny, int nz) {
  BlockSpec s;
  s.dim = 3;
  s.nx = nx;
  s.ny = ny;
  s.nz = nz;
  s.sx = 0.04;
  s.sy = 0.03;
  s.sz = 0.02;
  s.structure = structure;
  s.material.k1 = 1e4;
  s.material.c1 = 10.0;
  s.material.c2 = 100.0;
  return s;
}

int cells(int nx, int ny, int nz) { return (nx - 1) * (ny - 1) * (nz - 1); }

TEST(Lattice3D, HasAxisFaceAndBodyDiagonalEdgesOfEveryCell) {
  const int nx = 5, ny = 4, nz = 3;
  const Model m = make_block(spec3(Structure::kLattice, nx, ny, nz));
  const int axis = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
  const int face =
      2 * ((nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1));
  const int body = 4 * cells(nx, ny, nz);
  EXPECT_EQ(m.num_particles(), nx * ny * nz);
  EXPECT_EQ(m.num_edges(), axis + face + body);
  EXPECT_EQ(m.tetrahedra.size(), 6u * cells(nx, ny, nz));
}

TEST(Truss3D, HasTheEdgesOfItsTetrahedraOnly) {
  const int nx = 5, ny = 4, nz = 3;
  const Model m = make_block(spec3(Structure::kTruss, nx, ny, nz));
  const int axis = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
  const int face = (nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1);
  EXPECT_EQ(m.num_edges(), axis + face + cells(nx, ny, nz));
}

TEST(Block3D, TetrahedraFillTheBlockWithoutOverlap) {
  const BlockSpec s = spec3(Structure::kLattice, 4, 3, 3);
  const Model m = make_block(s);
  double total = 0.0;
  for (const auto& t : m.tetrahedra) {
    const Vec3 a = m.x0[t[0]];
    const double v = std::abs((m.x0[t[1]] - a).dot((m.x0[t[2]] - a).cross(m.x0[t[3]] - a))) / 6.0;
    EXPECT_GT(v, 0.0);
    total += v;
  }
  EXPECT_NEAR(total, s.sx * s.sy * s.sz, kRoundoff);
}

TEST(Block3D, FixesTheBottomLayerAndLetsThePlateTouchTheTopLayer) {
  const BlockSpec s = spec3(Structure::kLattice, 3, 3, 4);
  const Model m = make_block(s);
  for (int i = 0; i < m.num_particles(); ++i) {
    const double z = m.x0[i].z();
    if (z == 0.0) {
      EXPECT_EQ(m.flags[i], kFixed);
    } else if (std::abs(z - s.sz) < kRoundoff) {
      EXPECT_EQ(m.flags[i], kPlate);
    } else {
      EXPECT_EQ(m.flags[i], kFree);
    }
  }
  EXPECT_DOUBLE_EQ(m.height, s.sz);
  EXPECT_DOUBLE_EQ(m.size, s.sx);
  EXPECT_DOUBLE_EQ(m.top_area, s.sx * s.sy);
}

TEST(Block3D, MassesAddUpToDensityTimesVolumeTimesMassScale) {
  BlockSpec s = spec3(Structure::kTruss, 3, 4, 5);
  s.mass_scale = 250.0;
  const Model m = make_block(s);
  const double total = std::accumulate(m.mass.begin(), m.mass.end(), 0.0);
  EXPECT_NEAR(total, s.density * s.sx * s.sy * s.sz * s.mass_scale, kRoundoff);
  EXPECT_EQ(m.mass_scale, 250.0);
}

TEST(Block3D, EdgesStartAtRestWithTheirLengthAsNaturalLength) {
  const Model m = make_block(spec3(Structure::kLattice, 3, 3, 3));
  for (const Edge& e : m.edges) {
    const double l = (m.x0[e.e] - m.x0[e.s]).norm();
    EXPECT_DOUBLE_EQ(e.L, l);
    EXPECT_DOUBLE_EQ(e.l0, l);
  }
}

// Energy of the network when every edge is stretched by the hydrostatic strain eps.
double hydrostatic_energy(const Model& model, double eps) {
  Model m = model;
  m.gravity = Vec3::Zero();
  SimOptions options;
  options.check_stability = false;
  Simulator sim(m, options);
  for (int k = 0; k < m.num_edges(); ++k) sim.mutable_state().d[k] = (1.0 + eps) * m.edges[k].L;
  return sim.energy();
}

TEST(MaterialMapping, HydrostaticEnergyMatchesTheContinuumIn3D) {
  // Isotropic continuum, Poisson 1/4: K = 2E/3, U = 9/2 K eps^2 V = 3 E V eps^2.
  for (Structure st : {Structure::kLattice, Structure::kTruss}) {
    const BlockSpec s = spec3(st, 4, 5, 3);
    const double eps = 1e-3;
    const double expected = 3.0 * s.material.k1 * s.sx * s.sy * s.sz * eps * eps;
    EXPECT_NEAR(hydrostatic_energy(make_block(s), eps) / expected, 1.0, kRoundoff);
  }
}

TEST(MaterialMapping, AreaStrainEnergyMatchesTheContinuumIn2D) {
  // Plane network, Poisson 1/3: 2D bulk modulus 3E/4, U = 2 K (eps)^2 A sy = 1.5 E A sy eps^2.
  BlockSpec s = spec3(Structure::kTruss, 6, 1, 4);
  s.dim = 2;
  const double eps = 1e-3;
  const double expected = 1.5 * s.material.k1 * s.sx * s.sz * s.sy * eps * eps;
  EXPECT_NEAR(hydrostatic_energy(make_block(s), eps) / expected, 1.0, kRoundoff);
}

TEST(MaterialMapping, ViscositiesUseTheStiffnessFactorAndForcesTheTopParticleShare) {
  BlockSpec s = spec3(Structure::kLattice, 3, 3, 3);
  s.material.nonlinear = true;
  s.material.f1 = 100.0;  // Pa
  s.material.f2 = 400.0;
  s.material.c2_min = 1.0;
  const Model m = make_block(s);
  const EdgeMaterial& e = m.materials[0];
  EXPECT_NEAR(e.c1 / e.k1, s.material.c1 / s.material.k1, kRoundoff);
  EXPECT_NEAR(e.c2 / e.k1, s.material.c2 / s.material.k1, kRoundoff);
  EXPECT_NEAR(e.f1, 100.0 * s.sx * s.sy / 9.0, kRoundoff);
  EXPECT_NEAR(e.f2, 400.0 * s.sx * s.sy / 9.0, kRoundoff);
}

TEST(Block2D, LiesInTheXzPlaneWithTrianglesCoveringIt) {
  BlockSpec s = spec3(Structure::kTruss, 5, 1, 3);
  s.dim = 2;
  const Model m = make_block(s);
  EXPECT_EQ(m.num_particles(), 15);
  EXPECT_EQ(m.triangles.size(), 2u * 4 * 2);
  EXPECT_EQ(m.num_edges(), 4 * 3 + 5 * 2 + 8);  // axis edges + one diagonal per cell
  double area = 0.0;
  for (const auto& t : m.triangles) {
    const Vec3 ab = m.x0[t[1]] - m.x0[t[0]], ac = m.x0[t[2]] - m.x0[t[0]];
    area += 0.5 * std::abs(ab.z() * ac.x() - ab.x() * ac.z());
  }
  EXPECT_NEAR(area, s.sx * s.sz, kRoundoff);
  for (const Vec3& x : m.x0) EXPECT_EQ(x.y(), 0.0);
  s.structure = Structure::kLattice;
  EXPECT_EQ(make_block(s).num_edges(), 4 * 3 + 5 * 2 + 16);  // both diagonals
}

TEST(MakeBlock, RejectsASingleLayer) {
  BlockSpec s = spec3(Structure::kLattice, 3, 3, 1);
  EXPECT_THROW(make_block(s), Error);
  s = spec3(Structure::kLattice, 3, 3, 3);
  s.density = -1.0;
  EXPECT_THROW(make_block(s), Error);
}

}  // namespace
}  // namespace rheo
