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

// What a format must keep over the whole run against the double reference to pass
// (`rheo fixed`'s word-length judgement; docs/backends.md, "rheo fixed: the bounds"):
// positions (issue 5) and the plate force, the quantity the object model is for.
struct Bounds {
  // Max over steps and particles of the position error, relative to the object size.
  double position_rel = 1e-3;
  // Max over steps of |plate force - reference plate force|, relative to the reference's
  // peak plate force: a format whose positions stay close while its plate rule drops
  // forces (exact zeros at a large mass scale) fails here.
  double force_rel = 1e-2;
};

// Adds to every backend of a compare() result "meets_bounds" (completed the run and kept
// both bounds) and "bound_failures" (why not: refused or stopped, position, force), and
// the bounds themselves as "position_bound_rel" and "force_bound_rel".
void judge(nlohmann::json& result, const Bounds& bounds);

// Runs the comparison; the JSON holds per backend the checkpoint errors, the running
// maxima, the step reached (a backend stops at its first saturation, which is reported),
// and the samples for the plots.
// `backends`: backend::make_backend specs, e.g. "float", "fixed:q27_nearest_op18"; each
// runs the hardware model (driver::hardware_model) in lockstep with the reference.
nlohmann::json compare(const Scenario& scenario, const std::vector<std::string>& backends,
                       const CompareOptions& options);

}  // namespace rheo::fixedcmp
