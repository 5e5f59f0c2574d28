// Mesh generators for rectangular blocks (the shapes of the papers' experiments).
#pragma once

#include "sim/model.hpp"

namespace rheo {

enum class Structure {
  kTruss,    // 2D: triangles; 3D: tetrahedra (each cube split into 6 tetrahedra)
  kLattice,  // 26-neighbour lattice (Noborio et al.): axis, face and body diagonals
};

// Particles: a regular grid, nx x ny x nz in 3D, nx x nz in the x-z plane (y = 0) in 2D,
// spacing s/(n-1) per axis, the bottom layer at z = 0. Bottom layer kFixed when fix_bottom,
// top layer kPlate when plate_top. Elements: 2D cells split into two triangles with
// alternating diagonals; 3D cells split into 6 tetrahedra around the cell's main diagonal
// (Kuhn split, conforming). Edges: truss = the element edges; lattice = every pair of a
// cell's corners (2D: axis + both diagonals; 3D: axis, face and body diagonals, i.e. the
// 26-neighbour lattice). Both structures fill the element lists. Every edge starts at rest:
// L = l0 = its initial length, d = L.
//
// Material mapping (BlockSpec.material holds moduli):
//   k1, k2, spectrum k [Pa], c1, c2, c2_min, c3, spectrum c [Pa s]  ->  edge value = modulus * a,
//     3D: a = 6 V / sum_e l_e^2,   2D: a = 3 A sy / sum_e l_e^2  (sy = depth),
//   the factor that makes the energy of an affinely strained central-force network equal
//   to that of an isotropic continuum with Young's modulus E (Poisson 1/4; 1/3 in 2D).
//   The same factor turns viscosities into edge dampers (viscous stress ~ strain rate).
//   f1, f2 [Pa] (stresses)  ->  edge force = stress * top_area / (number of top particles),
//   the share of a uniform plate load carried by one top particle.
//   a_min, a_max, hardening, nonlinear are copied unchanged.
// Masses: density * sx * sy * sz / N * mass_scale each (uniform lumping; mass_scale is the
// documented inertia scaling for quasi-static runs, recorded in Model::mass_scale;
// make_block leaves gravity unscaled, see Model::mass_scale).
struct BlockSpec {
  int dim = 3;
  int nx = 5, ny = 5, nz = 5;                // particles per axis (ny ignored in 2D)
  double sx = 0.08, sy = 0.08, sz = 0.0125;  // extents [m]
  Structure structure = Structure::kLattice;
  double density = 1800.0;  // [kg/m^3]
  double mass_scale = 1.0;  // multiplies every particle mass (documented)
  EdgeMaterial material;    // moduli [Pa], viscosities [Pa s], f1/f2 [Pa]
  // Element forces beside the edges (model.hpp), copied into the model as given.
  TopologyMaintenance topology;
  VolumePreservation volume;
  bool fix_bottom = true;   // bottom layer fixed (the floor)
  bool plate_top = true;    // top layer touched by the plate
};

Model make_block(const BlockSpec& spec);

}  // namespace rheo
