// The per-edge half of the semi-implicit Euler step (docs/model.md), written once and
// templated on the scalar: every edge evaluated by the edge kernel (sim/edge_kernel.hpp)
// and its tension added to its two particles' forces. rheo::Simulator (double) and the
// float backend's loop (host/backend/float_simulator.hpp) both call it, beside the
// per-particle half (sim/particle_rule.hpp); the hardware's edge pass (hls::core_step,
// rtl/rheo_tem.sv) is the same loop in fixed point.
#pragma once

#include "sim/edge_kernel.hpp"
#include "sim/model.hpp"

namespace rheo {

// Per-edge state and results of one pass, as arrays indexed by edge (spectrum states:
// `spectrum_stride` per edge, edge after edge; null without a spectrum).
template <typename Real>
struct EdgePassArrays {
  const Real* d = nullptr;         // Voigt lengths
  const Real* m = nullptr;         // Maxwell-arm extensions
  const Real* spectrum = nullptr;  // spectrum-arm extensions
  int spectrum_stride = 0;
  Real* ddot = nullptr;    // out: Voigt length rates
  Real* mdot = nullptr;    // out: arm extension rates
  Real* sdot = nullptr;    // out: spectrum extension rates (with spectrum)
  Real* length = nullptr;  // out: edge lengths (may be null)
};

// Adds every edge's pull to `force` (not cleared here): +T (xe - xs) / l on the start, the
// opposite on the end. `lead` as in evaluate_edge (dt for the semi-implicit step, 0 for the
// right-hand side of the differential equation).
template <typename Real, typename Vec>
void add_edge_forces(const Model& model, const Vec* x, const Vec* v, const EdgePassArrays<Real>& a,
                     double lead, Vec* force) {
  const Edge* edges = model.edges.data();
  const EdgeMaterial* materials = model.materials.data();
  const int ne = model.num_edges();
  const int stride = a.spectrum_stride;
  for (int k = 0; k < ne; ++k) {
    const Edge& e = edges[k];
    const std::size_t arms = static_cast<std::size_t>(k) * stride;
    const EdgeEval<Real> r = evaluate_edge<Real>(
        materials[e.material], x[e.s], x[e.e], v[e.s], v[e.e], a.d[k], e.L, e.l0, a.m[k],
        stride > 0 ? a.spectrum + arms : nullptr, stride > 0 ? a.sdot + arms : nullptr, lead);
    const Real scale = r.tension / r.length;
    for (int c = 0; c < 3; ++c) {
      const Real pull = scale * (x[e.e][c] - x[e.s][c]);
      force[e.s][c] += pull;
      force[e.e][c] -= pull;
    }
    a.ddot[k] = r.ddot;
    a.mdot[k] = r.mdot;
    if (a.length) a.length[k] = r.length;
  }
}

}  // namespace rheo
