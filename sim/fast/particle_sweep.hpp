// The vectorised particle half of the fast path's step (fast_simulator.hpp): the rules of
// sim/particle_rule.hpp lane by lane for a range of particles at once: the explicit update
// (v += dt (f / m + g), x += dt v), fixed particles back at their rest position, the floor
// and the plate with both contact rules (apply_floor_and_plate). Differs from the scalar
// rules only in rounding: f / m is f * (1 / m), and the plate force of a range is summed
// lane-wise before the lanes are added.
#pragma once

#include <cstdint>

#include "sim/fast/worker_pool.hpp"

namespace rheo::fast {

struct ParticleSweepArgs {
  double* x[3] = {};  // positions and velocities (updated)
  double* v[3] = {};
  double* const* force = nullptr;  // per thread, per component: force[t * 3 + c]
  int threads = 1;  // force sums to add, in thread order (at most kMaxThreads)
  const int* touched = nullptr;  // thread t wrote its sums in [touched[2t], touched[2t+1])
  int own_thread = 0;  // the sweeping thread: its sums are set back to 0 once read
  const double* inverse_mass = nullptr;
  const double* free = nullptr;  // 1 for a particle that moves, 0 for a fixed one
  const double* x0[3] = {};      // rest positions (fixed particles)
  double gravity[3] = {};
  double dt = 0.0;
  bool floor = false;
  const double* plate = nullptr;  // 1 for a free plate particle, else 0
  double plate_z = 0.0;
  bool hold_while_pushing = false;  // PlateContact::kHoldWhilePushing
  bool grip = false;                // Model::plate_grip
  double* held = nullptr;           // 1 where the plate held the particle (updated)
  int begin = 0, end = 0;  // particles, multiples of kSlotAlign (the arrays are padded)
};

struct ParticleSweepResult {
  bool finite = true;  // every updated position and velocity is finite
  double plate_force_N = 0.0;
  int contacts = 0;
};

ParticleSweepResult sweep_particles(const ParticleSweepArgs& args);

}  // namespace rheo::fast
