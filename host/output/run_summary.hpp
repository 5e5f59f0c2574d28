// The figures a user reads off a plate test, taken per protocol phase rather than over the
// whole run: the force a push builds up to (and, named as such, any larger transient
// earlier in the push), the force at the end of each hold, when
// the plate loses contact on release, and the top surface's displacement at the end (the
// residual deformation once the plate has left). A maximum over the whole run would pick up
// whatever transient is largest, which is not what a load-cell reading is read for.
#pragma once

#include <string>
#include <vector>

#include "sim/protocol.hpp"

namespace rheo::output {

class RunSummary {
 public:
  explicit RunSummary(const PlateProtocol& protocol);

  // One sample: time [s], plate force [N], top-surface displacement [mm] (NaN when not
  // known at this sample). Samples come in increasing time.
  void add(double t, double force_N, double surface_mm);

  // One line per phase with its figure, e.g. "push 0-19.2 s: force at the end 7.02 N
  // (t = 19.2 s)". Empty when no sample was added.
  std::vector<std::string> lines() const;

 private:
  struct PhaseFigures {
    ProtocolPhase phase;
    int samples = 0;
    double peak_force = 0.0, peak_time = 0.0;  // push
    double last_force = 0.0, last_time = 0.0;  // hold (end of hold), any phase
    double contact_lost_time = -1.0;  // release: first sample with no force after the last contact
    double first_lost_time = -1.0;    // release: first sample with no force at all
    int recontacts = 0;               // release: times the object touched the plate again
    double last_surface = 0.0, last_surface_time = -1.0;
  };
  std::size_t phase_index(double t);

  std::vector<PhaseFigures> phases_;
  std::size_t current_ = 0;
};

}  // namespace rheo::output
