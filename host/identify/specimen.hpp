// The specimen model the fits run: the reference model's three-element edge kernel
// (sim/edge_kernel.hpp, docs/model.md) on a coarse mesh of the specimen, driven by a
// measured plate history, plus the observation side (sensor lag and offset).
//
// Coarse mesh: a 1-D column of two particles (bottom fixed on the floor, top touched by the
// plate) joined by one edge of rest length h (specimen height). Continuum moduli map onto
// the edge as k = E * A / h and c = eta * A / h (A = top area), so the column's force is
// stress * area and its strain is the engineering strain of the block. For a linear or
// homogeneously hardening material a column of n identical edges in series behaves exactly
// like one edge, so one edge loses nothing in the quasi-static regime.
//
// Time update: the particle is massless (the quasi-static limit m -> 0 of the reference
// Simulator's mass-point update), which removes the inertial stiffness that forces
// dt ~ 1e-6 s with clay viscosities (docs/model.md, explicit stability bound). In contact the top
// particle follows the plate and the edge states (Voigt length d, Maxwell-arm extension m)
// advance with the trapezoidal rule; out of contact the top particle moves so that the edge
// tension is zero and the states advance with backward Euler (stiff elastic recovery).
// Both are A-stable, so no explicit stability bound applies; the step is limited for
// accuracy to a fraction of the shortest relaxation time instead.
#pragma once

#include <string>
#include <vector>

#include "host/identify/measurement.hpp"
#include "sim/error.hpp"
#include "sim/fast/fast_simulator.hpp"
#include "sim/model.hpp"

namespace rheo::identify {

// Material and sensor parameters of the column in continuum units.
struct SpecimenParams {
  double E1 = 0.0;  // Voigt spring modulus [Pa]
  double c1 = 0.0;  // Voigt damper viscosity [Pa s]
  double c2 = 0.0;  // series damper viscosity [Pa s] (its low-stress value when nonlinear)
  double E2 = 0.0;  // parallel Maxwell arm spring [Pa] (0 = no arm)
  double c3 = 0.0;  // parallel Maxwell arm damper [Pa s]
  double damping_stress = 0.0;  // [Pa] stress at which the series viscosity reaches c2/ratio
  double damping_ratio = 1.0;   // c2 / c2_min (1 = linear damper)
  double hardening = 0.0;       // k_eff = k1 (1 + hardening e^2), e the column strain
  // Relaxation spectrum: parallel Maxwell arms standing for a power law
  // G(t) = spectrum_modulus (t / t_mid)^-spectrum_alpha over the window [t_lo, t_hi]
  // (sim/relaxation_spectrum.hpp); the window comes from the data, it is not fitted.
  double spectrum_modulus = 0.0;  // [Pa] G at t_mid = sqrt(t_lo t_hi) (0 = none)
  double spectrum_alpha = 0.5;
  double spectrum_t_lo = 0.0, spectrum_t_hi = 0.0;  // [s]
  double lag_s = 0.0;           // first-order load-cell lag [s] (0 = none)
  double offset_N = 0.0;        // constant load-cell offset [N]
};

// The edge material of these parameters in continuum units (moduli [Pa], viscosities
// [Pa s], the damper's switch stress f2 [Pa]); the column and the object mesh scale it to
// their edges.
EdgeMaterial continuum_material(const SpecimenParams& p);

// The coarse rheo::Model of the specimen (two particles, one edge) with these parameters.
Model coarse_model(const Geometry& g, const SpecimenParams& p);
std::string coarse_mesh_description(const Geometry& g);

// Which model of the specimen a fit runs.
//  - kObject (the default): the project's particle model of the specimen (sim/mesh.hpp
//    lattice or truss built from the file's geometry) run by the double reference model
//    (fast CPU path by default, SimulationOptions::cpu): the object the users simulate, see
//    object_specimen.hpp.
//  - kColumn: the 1-D column above, a fast first guess (quasi-static, one edge).
enum class SpecimenForm { kObject, kColumn };
std::string specimen_form_name(SpecimenForm f);  // "object" or "column"

// Mesh of the object model: particles per axis (ny ignored in 2-D), lattice or truss.
// nx = 0 (the default, "2d:auto") takes nz = 3 layers and as many columns as keep the cells
// square: nx = round((nz - 1) width / height) + 1, within 2..12. The default is 2-D because
// the three-element lattice in 3-D loses its shape under a long hold when one cell spans the
// thickness (the force collapses; docs/identify.md, known limits).
struct ObjectMesh {
  int dim = 2;
  int nx = 0, ny = 2, nz = 3;
  bool truss = false;
  ObjectMesh resolved(const Geometry& g) const;  // nx = 0 replaced as described
  // Next finer mesh (one more particle along each axis), for the mesh-convergence check.
  ObjectMesh finer() const;
  std::string text() const;  // "2d:3x3", "3d:3x2x3" (the --mesh syntax)
};
// Parses "2d:auto", "2d:NXxNZ" or "3d:NXxNYxNZ" (optionally ":truss"); throws rheo::Error naming the
// option and the expected form.
ObjectMesh parse_object_mesh(const std::string& text);

struct SimulationOptions {
  SpecimenForm form = SpecimenForm::kObject;
  ObjectMesh mesh;
  // Object model: explicit steps per sample interval (the inertia of the scaled masses
  // then fades within a small fraction of a sample, see object_specimen.hpp).
  int steps_per_sample = 10;
  double max_dt = 0.1;                  // [s] upper bound of the time step
  double steps_per_time_constant = 10;  // accuracy: dt <= shortest relaxation time / this
  long max_steps = 20000;               // column: cap on the total steps (dt grows instead)
  long max_object_steps = 2000000;      // object: cap on the total steps (refused above)
  fast::CpuOptions cpu;                 // object: the reference's CPU path (sim/fast/)
};

struct Prediction {
  std::vector<double> force_N;     // load-cell reading at each sample time
  std::vector<double> surface_mm;  // top-surface displacement at each sample time
  std::vector<bool> contact;       // plate touching the top at each sample time
};

// What the fits run, in words (report, fit.json): the object mesh or the column.
std::string specimen_description(const Geometry& g, const SimulationOptions& o);

// The object model could not run a record with some parameters (a relaxation too fast for
// the record's sampling, too many steps, a collapse): a failure of the model form, for which
// the 1-D column is a way out, unlike a failure of the data (too few samples), which every
// form shares.
class ObjectModelError : public Error {
 public:
  using Error::Error;
};

// Runs the specimen model (options.form) under the measurement's plate history (linear between samples; the
// plate starts at 0 at t = 0 and moves linearly to the first sample when t[0] > 0) and
// returns the predicted readings at the sample times. Throws rheo::Error on non-finite
// state (numerical trouble) or non-positive parameters, ObjectModelError where the object
// model fails.
Prediction simulate(const Measurement& protocol, const SpecimenParams& params,
                    const SimulationOptions& options = {});

}  // namespace rheo::identify
