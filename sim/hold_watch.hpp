// A collapse under a held plate is never a result. While the plate holds still and presses
// on the object, no work goes into it: a passive viscoelastic object can only come to rest,
// and its kinetic energy can only decay. When it instead grows far beyond what the plate's
// motion gave the object, the object is giving way by itself: a slender lattice buckling
// (a mechanical instability of the mesh, not the material's relaxation; docs/model.md,
// "When the mesh collapses"). HoldWatch sees the states a run looks at and fails the run
// then, naming the time, the fastest particle and where it is.
//
// Criterion: during a hold (the plate at the same height as at the previous look, and
// pressing: plate force > 0), the kinetic energy exceeds kGrowth times the largest kinetic
// energy seen while the plate moved. Before the plate has moved nothing is judged.
#pragma once

#include <string>
#include <vector>

#include "sim/model.hpp"

namespace rheo {

class HoldWatch {
 public:
  // The largest ratio of a hold's kinetic energy to the plate-driven one that passes.
  static constexpr double kGrowth = 10.0;

  explicit HoldWatch(const Model& model) : mass_(model.mass) {}

  // One look at the run: time [s], plate displacement [mm], plate force [N] and the state.
  // Returns "" or the description of the collapse.
  std::string observe(double t, double plate_mm, double force_N, const State& state);
  // Throws rheo::Error with observe's description.
  void check(double t, double plate_mm, double force_N, const State& state);

 private:
  std::vector<double> mass_;  // the particles' masses [kg]
  bool looked_ = false;
  double last_plate_mm_ = 0.0;
  double driven_ = 0.0;  // largest kinetic energy while the plate moved [J]
};

}  // namespace rheo
