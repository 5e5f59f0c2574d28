#include "host/output/run_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rheo::output {

namespace {

// Relative difference below which two forces are reported as one.
constexpr double kSameForce = 1e-3;

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

}  // namespace

RunSummary::RunSummary(const PlateProtocol& protocol) {
  for (const ProtocolPhase& p : protocol.phases()) phases_.push_back({p});
  if (phases_.empty()) {
    // A protocol with a single knot holds the plate still from t = 0.
    const double mm = protocol.plate_mm.empty() ? 0.0 : protocol.plate_mm.front();
    phases_.push_back({{mm > 0.0 ? PhaseKind::kHold : PhaseKind::kRest, 0.0, 0.0}});
  }
}

std::size_t RunSummary::phase_index(double t) {
  // A sample at a phase's end time belongs to that phase (the end of a push is its peak);
  // samples past the protocol's end belong to the last phase.
  while (current_ + 1 < phases_.size() && t > phases_[current_].phase.t_end) ++current_;
  return current_;
}

void RunSummary::add(double t, double force_N, double surface_mm) {
  PhaseFigures& f = phases_[phase_index(t)];
  if (f.samples == 0 || force_N > f.peak_force) {
    f.peak_force = force_N;
    f.peak_time = t;
  }
  f.last_force = force_N;
  f.last_time = t;
  // The object may leave the plate and touch it again (a block springing back as the plate
  // rises): the separation reported is the last one, and the touches between are counted.
  if (force_N <= 0.0) {
    if (f.contact_lost_time < 0.0) f.contact_lost_time = t;
    if (f.first_lost_time < 0.0) f.first_lost_time = t;
  } else if (f.contact_lost_time >= 0.0) {
    f.contact_lost_time = -1.0;
    ++f.recontacts;
  }
  if (std::isfinite(surface_mm)) {
    f.last_surface = surface_mm;
    f.last_surface_time = t;
  }
  ++f.samples;
}

std::vector<std::string> RunSummary::lines() const {
  std::vector<std::string> out;
  double last_push_peak = 0.0;
  double release_end = -1.0;
  for (std::size_t i = 0; i < phases_.size(); ++i) {
    const PhaseFigures& f = phases_[i];
    if (f.samples == 0) continue;
    const bool last = i + 1 == phases_.size() ||
                      std::all_of(phases_.begin() + i + 1, phases_.end(),
                                  [](const PhaseFigures& g) { return g.samples == 0; });
    std::string line = std::string(phase_name(f.phase.kind)) +
                       format(" %g-%g s: ", f.phase.t_begin, last ? f.last_time : f.phase.t_end);
    switch (f.phase.kind) {
      case PhaseKind::kPush:
        // The figure a load cell is read for is the force the push builds up to. A larger
        // force earlier in the push that the force then falls from is a transient (a
        // viscoelastic body under a steady push answers with a rising force): it is named
        // as such rather than reported as the peak.
        line += format("force at the end %.4g N (t = %.4g s)", f.last_force, f.last_time);
        if (f.peak_force > f.last_force * (1.0 + kSameForce)) {
          line += format("; an early transient reaches %.4g N at t = %.4g s", f.peak_force,
                         f.peak_time);
        }
        last_push_peak = f.last_force;
        break;
      case PhaseKind::kHold:
        line += format("force at the end %.4g N (t = %.4g s)", f.last_force, f.last_time);
        if (last_push_peak > 0.0) {
          line +=
              format(", %.0f %% of the push's end force", 100.0 * f.last_force / last_push_peak);
        }
        break;
      case PhaseKind::kRelease:
        if (f.contact_lost_time >= 0.0) {
          line += format("the plate leaves the object at t = %.4g s", f.contact_lost_time);
        } else {
          line += format("the plate stays in contact (force %.4g N at t = %.4g s)", f.last_force,
                         f.last_time);
        }
        if (f.recontacts > 0) {
          line += format(" (it first left at t = %.4g s; the object touched the plate again %.0f",
                         f.first_lost_time, f.recontacts) +
                  (f.recontacts == 1 ? " time)" : " times)");
        }
        release_end = f.phase.t_end;
        break;
      case PhaseKind::kRest:
        line += format("force %.4g N", f.last_force);
        break;
    }
    if (last && f.last_surface_time >= 0.0) {
      if (f.phase.kind == PhaseKind::kRest && release_end >= 0.0) {
        line += format(
            "; residual deformation %.4g mm (top surface at t = %.4g s, %.4g s after "
            "release)",
            f.last_surface, f.last_surface_time, f.last_surface_time - release_end);
      } else {
        line += format("; top surface %.4g mm down at t = %.4g s (plate not yet released)",
                       f.last_surface, f.last_surface_time);
      }
    }
    out.push_back(line);
  }
  return out;
}

}  // namespace rheo::output
