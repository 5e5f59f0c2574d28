// Fixed-point vs float vs double: runs one scenario on the double reference backend and on
// other backends (host/backend: float, the bit-true arithmetic in several fixed-point
// formats, or any other), all in lockstep through the one Backend interface, and measures
// each against double every step: position error relative to the object size
// (max over particles and RMS over particles) and plate-force error.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/scenario.hpp"

namespace rheo::fixedcmp {

struct CompareOptions {
  long long steps = 100000;
  std::vector<long long> checkpoints{1000, 10000, 100000};
  int lanes = 1;
  int plot_points_per_decade = 20;               // error-vs-step samples on the log axis
  int force_curve_points = 2000;                 // samples of the force curves
  std::function<void(long long step)> progress;  // called after every step when set
};

// Runs the comparison; the JSON holds per backend the checkpoint errors, the running
// maxima, the step reached (a backend stops at its first saturation, which is reported),
// and the samples for the plots.
// `backends`: backend::make_backend specs, e.g. "float", "fixed:q27_nearest_op18"; each
// runs the hardware model (driver::hardware_model) in lockstep with the reference.
nlohmann::json compare(const Scenario& scenario, const std::vector<std::string>& backends,
                       const CompareOptions& options);

}  // namespace rheo::fixedcmp
