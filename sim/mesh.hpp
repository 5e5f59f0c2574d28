// Mesh generators for rectangular blocks (the shapes of the papers' experiments).
#pragma once

#include "sim/model.hpp"

namespace rheo {

enum class Structure {
  kTruss,    // 2D: triangles; 3D: tetrahedra (each cube split into 6 tetrahedra)
  kLattice,  // 26-neighbour lattice (Noborio et al.): axis, face and body diagonals
};

// Material given as continuum-like moduli; the generator turns them into edge
// coefficients (k1 = E * a, c = eta * a for an edge of length a, scaled per edge family).
struct BlockSpec {
  int dim = 3;
  int nx = 5, ny = 5, nz = 5;              // particles per axis (ny ignored in 2D)
  double sx = 0.08, sy = 0.08, sz = 0.0125;  // extents [m]
  Structure structure = Structure::kLattice;
  double density = 1800.0;                 // [kg/m^3]
  double mass_scale = 1.0;                 // multiplies every particle mass (documented)
  EdgeMaterial material;                   // per unit-length-normalised coefficients (see mesh.cpp)
  bool fix_bottom = true;                  // bottom layer fixed (the floor)
  bool plate_top = true;                   // top layer touched by the plate
};

Model make_block(const BlockSpec& spec);

}  // namespace rheo
