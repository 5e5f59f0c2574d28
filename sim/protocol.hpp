// Plate displacement history: piecewise-linear plate_mm(t) (downward displacement from
// first contact, docs/data-format.md), e.g. push at constant speed, hold, release.
#pragma once

#include <string>
#include <vector>

namespace rheo {

// What the plate does between two times: the phases a user reads a test by.
enum class PhaseKind { kPush, kHold, kRelease, kRest };
const char* phase_name(PhaseKind kind);  // "push", "hold", "release", "rest"

struct ProtocolPhase {
  PhaseKind kind;
  double t_begin = 0.0;  // [s]
  double t_end = 0.0;    // [s]
};

struct PlateProtocol {
  std::vector<double> t;         // [s], strictly increasing, t[0] = 0
  std::vector<double> plate_mm;  // plate displacement [mm] at t (positive = pushed down)

  // Linear interpolation; constant beyond the ends.
  double displacement_mm(double time) const;
  double duration() const { return t.empty() ? 0.0 : t.back(); }

  // The protocol cut into phases: push (plate going down), hold (at rest in contact,
  // plate_mm > 0), release (going up) and rest (at rest out of contact, plate_mm <= 0).
  // Neighbouring segments of one kind are merged; a run past the last knot belongs to the
  // last phase.
  std::vector<ProtocolPhase> phases() const;

  // push at speed_mm_s to depth_mm, hold for hold_s, release (retract) at speed_mm_s
  // back to 0, then stay for after_s.
  static PlateProtocol push_hold_release(double depth_mm, double speed_mm_s, double hold_s,
                                         double after_s);
};

}  // namespace rheo
