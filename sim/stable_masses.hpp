// Particle masses as a numerical device, for quasi-static runs of a soft specimen.
//
// A real clay specimen's particles weigh grams, and explicit steps would have to be about
// 1e-7 s. In a quasi-static test (a plate pushing at mm/s, forces read every few ms) inertia
// plays no part, so each particle gets the smallest mass for which the explicit step dt is
// stable: by the bound rheo::max_stable_dt uses (simulator.hpp), semi-implicit Euler with
// a particle's summed edge stiffness K_i and largest instantaneous damping C_i is stable when
// dt^2 (2 K_i / m_i) + 2 dt (2 C_i / m_i) < 4, i.e. for m_i > K_i dt^2 / 2 + C_i dt. The mass
// is that bound divided by `safety` (0.6 by default: strain hardening stiffens the edges
// beyond what the bound sees). A particle's velocity then relaxes within about a step, and
// a disturbance crosses nz layers in a few times nz^2 steps.
//
// The fits' object model (host/identify/object_specimen.hpp) and a scenario with
// "integrator": {"masses": "stable_step"} (sim/scenario.hpp) use this one rule, so a
// specimen simulated by `rheo simulate` and the model a fit runs are the same model.
// Gravity has no meaning with such masses: both run without it (a load cell is tared with the
// specimen on it, and a soft specimen's weight is far below the forces measured).
#pragma once

#include "sim/model.hpp"

namespace rheo {

inline constexpr double kStableMassSafety = 0.6;

// Sets every particle's mass for step dt as above (a particle without edges gets 1 kg),
// model.mass_scale to 1 and model.gravity to zero.
void assign_stable_step_masses(Model& model, double dt, double safety = kStableMassSafety);

}  // namespace rheo
