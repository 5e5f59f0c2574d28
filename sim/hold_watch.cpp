#include "sim/hold_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/error.hpp"

namespace rheo {

std::string HoldWatch::observe(double t, double plate_mm, double force_N, const State& state) {
  double kinetic = 0.0, fastest_speed = -1.0;
  int fastest = -1;
  for (std::size_t i = 0; i < mass_.size(); ++i) {
    const double speed2 = state.v[i].squaredNorm();
    kinetic += 0.5 * mass_[i] * speed2;
    if (speed2 > fastest_speed) {
      fastest_speed = speed2;
      fastest = static_cast<int>(i);
    }
  }
  const bool holding = looked_ && plate_mm == last_plate_mm_;
  if (looked_ && !holding) driven_ = std::max(driven_, kinetic);
  looked_ = true;
  last_plate_mm_ = plate_mm;
  if (!holding || !(force_N > 0.0) || !(driven_ > 0.0) || !(kinetic > kGrowth * driven_)) {
    return "";
  }
  const Vec3& x = state.x[static_cast<std::size_t>(fastest)];
  char text[640];
  std::snprintf(text, sizeof text,
                "the object gave way under the held plate at t = %.6g s: its kinetic energy "
                "grew to %.3g J, %.0f times the %.3g J the plate's motion gave it, while the "
                "plate held still at %.4g mm; particle %d near (%.4g, %.4g, %.4g) m moves at "
                "%.3g mm/s. A passive object held still can only come to rest: the mesh is "
                "collapsing (buckling), and its forces are not the material's (docs/model.md, "
                "\"When the mesh collapses\": /protocol/plate_grip, a finer mesh)",
                t, kinetic, kinetic / driven_, driven_, plate_mm, fastest, x.x(), x.y(), x.z(),
                std::sqrt(fastest_speed) * 1e3);
  return text;
}

void HoldWatch::check(double t, double plate_mm, double force_N, const State& state) {
  if (std::string what = observe(t, plate_mm, force_N, state); !what.empty()) throw Error(what);
}

}  // namespace rheo
