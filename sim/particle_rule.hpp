// The per-particle half of the semi-implicit Euler step (docs/model.md), written once and
// templated on the scalar: the explicit velocity and position update of a free particle and
// the floor and plate rules after it. rheo::Simulator (double) and the float backend's loop
// (host/backend/float_simulator.hpp) both call it, so the two cannot drift apart; the
// hardware's MPM (hls::mpm_particle, rtl/rheo_mpm.sv) is the same rule in fixed point.
#pragma once

#include <algorithm>
#include <cstdint>

#include "sim/model.hpp"

namespace rheo {

// True for particles pinned at their rest position (no update at all).
inline bool is_fixed_particle(std::uint8_t flag) { return flag == kFixed; }

// The explicit update of a free particle: v += dt (f / m + g [+ external / m]), x += dt v.
// `external` may be null (no external force).
template <typename Real, typename Vec>
void explicit_update(const Model& model, int i, const Vec& f, const Vec& g, const Vec* external,
                     Real dt, Vec& x, Vec& v) {
  const Real mass = static_cast<Real>(model.mass[i]);
  for (int c = 0; c < 3; ++c) {
    Real accel = f[c] / mass + g[c];
    if (external) accel += (*external)[c] / mass;
    v[c] += dt * accel;
    x[c] += dt * v[c];
  }
}

// The floor and, for a plate particle, the plate rule at height plate_z, after the update
// moved the particle from `start` (its position when the step began). `held` is whether the
// plate held the particle in the previous step; it is updated. Returns true when the plate
// holds the particle now: its force_z then counts in the plate force. With
// Model::plate_grip a held particle keeps its lateral position (x, y of `start`) and has
// no lateral velocity.
template <typename Real, typename Vec>
bool apply_floor_and_plate(const Model& model, int i, const Vec& start, Real plate_z, Real dt,
                           Real force_z, Vec& x, Vec& v, std::uint8_t& held) {
  const Real z_start = start[2];
  if (model.floor && x[2] < Real(0)) {
    x[2] = Real(0);
    v[2] = std::max(v[2], Real(0));
  }
  if (model.flags[i] != kPlate) return false;
  const Real plate_velocity = (plate_z - z_start) * (Real(1) / dt);
  // Through the plate, or held in the previous step, exactly on the plate now and still
  // pushing (force_z > 0). On rounded positions (float) a held particle whose force moves
  // it less than half a position step per step beyond the plate lands exactly on it, and
  // the position test alone dropped it and its force (exact zeros, docs/backends.md "Plate
  // force resolution"); in double the tie does not occur in practice. The fixed-point
  // cores decide the same on their P word (hls::mpm_particle).
  if (x[2] > plate_z || (held && x[2] == plate_z && force_z > Real(0))) {
    x[2] = plate_z;
    // The held particle moves with the plate: its velocity must match its position change,
    // otherwise the edges never see the plate's strain rate (see simulator.hpp).
    v[2] = std::min(v[2], plate_velocity);
  } else if (held && force_z > Real(0) &&
             model.plate_contact == PlateContact::kHoldWhilePushing) {
    // Still pushing the plate: it stays on it (see PlateContact in model.hpp).
    x[2] = plate_z;
    v[2] = plate_velocity;
  } else {
    held = 0;
    return false;
  }
  held = 1;
  if (model.plate_grip) {
    for (int c = 0; c < 2; ++c) {
      x[c] = start[c];
      v[c] = Real(0);
    }
  }
  return true;
}

}  // namespace rheo
