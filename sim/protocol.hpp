// Plate displacement history: piecewise-linear plate_mm(t) (downward displacement from
// first contact, design.md §7), e.g. push at constant speed, hold, release.
#pragma once

#include <vector>

namespace rheo {

struct PlateProtocol {
  std::vector<double> t;         // [s], strictly increasing, t[0] = 0
  std::vector<double> plate_mm;  // plate displacement [mm] at t (positive = pushed down)

  // Linear interpolation; constant beyond the ends.
  double displacement_mm(double time) const;
  double duration() const { return t.empty() ? 0.0 : t.back(); }

  // push at speed_mm_s to depth_mm, hold for hold_s, release (retract) at speed_mm_s
  // back to 0, then stay for after_s.
  static PlateProtocol push_hold_release(double depth_mm, double speed_mm_s, double hold_s,
                                         double after_s);
};

}  // namespace rheo
