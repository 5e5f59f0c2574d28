// The signed measure of a mesh element and its gradient, written once and templated on the
// scalar: rheo::Simulator (double; volume preservation and topology maintenance) and the
// float backend's loop (host/backend/float_simulator.hpp) both call it, so the two cannot
// drift apart. The hardware's volume element (hls::volume_element, rtl/rheo_volume.sv)
// computes the same quantities in fixed point, six and 2 Y times larger.
#pragma once

#include <cstddef>
#include <type_traits>

#include "sim/model.hpp"

namespace rheo {

// A model's mesh elements: triangles (dim 2) or tetrahedra (dim 3).
inline std::size_t element_count(const Model& m) {
  return m.dim == 2 ? m.triangles.size() : m.tetrahedra.size();
}
inline int element_vertex_count(const Model& m) { return m.dim == 2 ? 3 : 4; }
inline int element_vertex(const Model& m, std::size_t element, int v) {
  return m.dim == 2 ? m.triangles[element][v] : m.tetrahedra[element][v];
}

// Signed area in the x-z plane (dim 2, vertices p[0..2]) or signed volume (dim 3, p[0..3])
// and, when grad is not null, its gradient with respect to each vertex.
// 2-D: A = ((b-a)_z (c-a)_x - (b-a)_x (c-a)_z) / 2. 3-D: V = (b-a) . ((c-a) x (d-a)) / 6.
// Vec: three components by operator[], constructible from three scalars.
template <typename Real, typename Vec>
Real signed_measure(int dim, const Vec* p, std::type_identity_t<Vec>* grad) {
  auto sub = [](const Vec& u, const Vec& w) { return Vec{u[0] - w[0], u[1] - w[1], u[2] - w[2]}; };
  auto cross = [](const Vec& u, const Vec& w) {
    return Vec{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  };
  const Real half = Real(0.5), six = Real(6), zero = Real(0);
  const Vec ab = sub(p[1], p[0]), ac = sub(p[2], p[0]);
  if (dim == 2) {
    const Real area = half * (ab[2] * ac[0] - ab[0] * ac[2]);
    if (grad) {
      grad[1] = Vec{half * -ac[2], zero, half * ac[0]};
      grad[2] = Vec{half * ab[2], zero, half * -ab[0]};
      grad[0] = Vec{-(grad[1][0] + grad[2][0]), zero, -(grad[1][2] + grad[2][2])};
    }
    return area;
  }
  const Vec ad = sub(p[3], p[0]);
  const Vec g1 = cross(ac, ad);
  const Real volume = (ab[0] * g1[0] + ab[1] * g1[1] + ab[2] * g1[2]) / six;
  if (grad) {
    const Vec g2 = cross(ad, ab), g3 = cross(ab, ac);
    for (int c = 0; c < 3; ++c) {
      grad[1][c] = g1[c] / six;
      grad[2][c] = g2[c] / six;
      grad[3][c] = g3[c] / six;
      grad[0][c] = -(grad[1][c] + grad[2][c] + grad[3][c]);
    }
  }
  return volume;
}

// The factor of area/volume preservation on an element's measure gradient: the force on
// vertex i is volume_pressure(kv, V, V0) dV/dx_i, the gradient of kv (V - V0)^2 / (2 |V0|).
// Divided by |V0|: the signed measure is negative for a clockwise element.
template <typename Real>
Real volume_pressure(Real kv, Real volume, Real rest) {
  return -kv * (volume - rest) / (rest < Real(0) ? -rest : rest);
}

}  // namespace rheo
