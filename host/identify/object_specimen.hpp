// The object model of a specimen: the project's particle model (sim/mesh.hpp) of the block
// the measurement file describes, run by the double reference model (the `ref` backend: its
// fast CPU path, or rheo::Simulator with SimulationOptions::cpu) under the file's plate
// history. This is the simulation users run on the reference and on the hardware, so
// a misfit found here is a misfit of the object simulation, not of a stand-in.
//
// Mesh: make_block with the file's geometry (x = width, y = depth, z = height; 2-D meshes
// lie in the x-z plane with the depth as thickness), bottom layer fixed on the floor, top
// layer under the plate. Continuum moduli and viscosities become edge coefficients by
// make_block's mapping; the nonlinear damper's stress scale becomes an edge force by the same
// mapping (f = stress x top area / top particles). No gravity: a load cell is tared with
// the specimen on it, and the weight of a soft specimen is far below the forces fitted.
//
// Masses: explicit integration needs inertia, and a specimen's real particle masses would
// force steps of microseconds. The masses are a numerical device here: each particle gets
// the smallest mass for which the semi-implicit Euler step dt is stable by the bound of
// rheo::max_stable_dt (its stiffness K_i and damping C_i: m_i = (K_i dt^2 / 2 + C_i dt) / s,
// s = 0.6), so its velocity relaxes within about one step, and the velocity diffuses through
// the nz layers in a few times nz^2 steps. The masses follow the step: where the samples grow
// sparse (log-spaced relaxation tables) the step grows with them and the simulation continues
// from the same state with the new step's masses. dt is the sample interval divided by
// steps_per_sample (and at most 1/10 of the shortest relaxation time): with the default of
// 10, inertia has faded within the first steps after a sample (measured: the forces of 10
// and 160 steps per sample differ by 1 % in the first sample of a push, 0.03 % later). The plate
// holds a particle while the object pushes against it (PlateContact::kHoldWhilePushing), so the
// force is continuous at every switch of the protocol.
#pragma once

#include "host/backend/backend.hpp"
#include "host/identify/measurement.hpp"
#include "host/identify/specimen.hpp"
#include "sim/model.hpp"

namespace rheo::identify {

// The object model with these parameters and masses for time step dt.
Model object_model(const Geometry& g, const SpecimenParams& p, const ObjectMesh& mesh, double dt);

// The time steps the object model takes for this protocol and these parameters: per sample
// interval, the interval / steps_per_sample (at most max_dt and 1/steps_per_time_constant of
// the shortest relaxation time), rounded down to a power of two times the smallest. Throws
// rheo::Error when the shortest relaxation time is far below the shortest sample interval.
struct StepPlan {
  std::vector<double> dt;  // step used up to each sample [s]
  double smallest = 0.0;   // [s]
  double steps = 0.0;      // total steps over the record
};
StepPlan step_plan(const Measurement& protocol, const SpecimenParams& p,
                   const SimulationOptions& options);

// On the reference model (the fits), or on any backend (driven through backend::Backend,
// e.g. to check the fitted model on the fixed-point core).
Prediction simulate_object(const Measurement& protocol, const SpecimenParams& p,
                           const SimulationOptions& options);
Prediction simulate_object(const Measurement& protocol, const SpecimenParams& p,
                           const SimulationOptions& options, backend::Backend& engine);

}  // namespace rheo::identify
