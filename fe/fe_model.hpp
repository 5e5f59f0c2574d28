// The continuum (finite-element) forward model: the public API in one include.
//
//   Mesh mesh = make_rectangle(0.08, 0.08, 4, 4);                       // fe/mesh.hpp
//   ViscoelasticLaw law = ViscoelasticLaw::four_element(FourElementNetwork::kB, p, 0.35);
//   ContinuumModel model(mesh, law, {Formulation::kPlaneStress, 0.0125}); // fe/solver.hpp
//   PlateRecord rec = run_plate_history(model, seed002_protocol(0.5e-3, 9.6e-3, 47.88, 0.5e-3, 30), 0.1);
//
// See docs/fe.md for the equations, boundary conditions and limits.
#pragma once

#include <functional>
#include <vector>

#include "fe/law.hpp"
#include "fe/mesh.hpp"
#include "fe/solver.hpp"

namespace rheo::fe {

// A plate depth history (compression positive) [m] as a function of time [s], and its length.
struct PlateHistory {
  std::function<double(double)> depth_m;
  double duration_s = 0.0;
};

// Seed 002's push-hold-release: pushed at push_speed to depth, held for hold_s, drawn back at
// release_speed to depth 0, and left there for after_s. Throws rheo::Error naming a
// parameter that is not positive (after_s, hold_s: not negative) and finite.
PlateHistory push_hold_release(double push_speed_m_s, double depth_m, double hold_s,
                               double release_speed_m_s, double after_s);

struct PlateRecord {
  std::vector<double> t_s, plate_depth_m, force_N;
  std::vector<std::vector<double>> top_uz_m;  // per step: mesh.top_nodes' vertical displacement
  std::vector<int> contact_nodes;             // per step
};

// Steps the model from its present time to history.duration_s in steps of dt (the last one
// shortened to end on the duration), recording every step. Errors of the model pass through.
PlateRecord run_plate_history(ContinuumModel& model, const PlateHistory& history, double dt_s);

}  // namespace rheo::fe
