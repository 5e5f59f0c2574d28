// The double-precision reference simulator: owns a Model and its State and advances
// them in time. The per-edge physics lives in edge_kernel.hpp (templated, stateless);
// this class holds storage and the time loop only.
#pragma once

#include <string>

#include "sim/model.hpp"

namespace rheo {

enum class Integrator { kSemiImplicitEuler, kRK4 };

struct SimOptions {
  double dt = 1e-4;                                   // [s]
  Integrator integrator = Integrator::kSemiImplicitEuler;
  bool check_stability = true;                        // refuse dt above the explicit bound
};

// What one step reports: the plate's reaction force (positive in compression: the sum
// of the z-components of the internal forces on the particles the plate holds), the
// plate height used and how many particles touch it.
struct StepReport {
  double plate_force_N = 0.0;
  double plate_z = 0.0;
  int contacts = 0;
};

// Largest dt for which the explicit integrator is stable on this model (estimate from
// per-particle stiffness and damping sums, with a safety factor). See simulator.cpp.
double max_stable_dt(const Model& model, Integrator integrator);

class Simulator {
 public:
  // Throws rheo::Error if the model is invalid or dt is above max_stable_dt (the message
  // gives the largest safe dt).
  Simulator(Model model, SimOptions options);

  // Advances one step of dt with the plate at height plate_z [m] (no contact when the
  // plate is above every plate particle). Throws rheo::Error on non-finite state.
  StepReport step(double plate_z);

  const Model& model() const { return model_; }
  const State& state() const { return state_; }
  State& mutable_state() { return state_; }
  const SimOptions& options() const { return options_; }

  // Internal forces (edges, topology maintenance, volume) on every particle for a given
  // state, without gravity or constraints. Exposed for tests (momentum, moments).
  void internal_forces(const State& s, std::vector<Vec3>& f, std::vector<double>& ddot,
                       std::vector<double>& mdot) const;

  // Total mechanical energy (kinetic + Voigt/Maxwell springs + gravity potential).
  double energy() const;

 private:
  Model model_;
  SimOptions options_;
  State state_;
};

}  // namespace rheo
