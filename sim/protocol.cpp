#include "sim/protocol.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/error.hpp"

namespace rheo {

double PlateProtocol::displacement_mm(double time) const {
  if (t.empty()) return 0.0;
  if (time <= t.front()) return plate_mm.front();
  if (time >= t.back()) return plate_mm.back();
  // First knot strictly after `time`; the segment [hi-1, hi] contains it.
  const auto hi = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  const std::size_t lo = hi - 1;
  const double w = (time - t[lo]) / (t[hi] - t[lo]);
  return plate_mm[lo] + w * (plate_mm[hi] - plate_mm[lo]);
}

const char* phase_name(PhaseKind kind) {
  switch (kind) {
    case PhaseKind::kPush:
      return "push";
    case PhaseKind::kHold:
      return "hold";
    case PhaseKind::kRelease:
      return "release";
    case PhaseKind::kRest:
      return "rest";
  }
  return "?";
}

std::vector<ProtocolPhase> PlateProtocol::phases() const {
  std::vector<ProtocolPhase> out;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double rise = plate_mm[i] - plate_mm[i - 1];
    PhaseKind kind;
    if (rise > 0.0) {
      kind = PhaseKind::kPush;
    } else if (rise < 0.0) {
      kind = PhaseKind::kRelease;
    } else {
      kind = plate_mm[i] > 0.0 ? PhaseKind::kHold : PhaseKind::kRest;
    }
    if (!out.empty() && out.back().kind == kind) {
      out.back().t_end = t[i];
    } else {
      out.push_back({kind, t[i - 1], t[i]});
    }
  }
  return out;
}

PlateProtocol PlateProtocol::push_hold_release(double depth_mm, double speed_mm_s, double hold_s,
                                               double after_s) {
  auto check = [](const char* field, double value, bool ok, const char* expected) {
    if (!ok) {
      throw Error(std::string("push_hold_release: ") + field + " = " + std::to_string(value) +
                  ", expected " + expected);
    }
  };
  check("depth_mm", depth_mm, std::isfinite(depth_mm) && depth_mm > 0.0, "a finite value > 0");
  check("speed_mm_s", speed_mm_s, std::isfinite(speed_mm_s) && speed_mm_s > 0.0,
        "a finite value > 0");
  check("hold_s", hold_s, std::isfinite(hold_s) && hold_s >= 0.0, "a finite value >= 0");
  check("after_s", after_s, std::isfinite(after_s) && after_s >= 0.0, "a finite value >= 0");

  PlateProtocol p;
  // Zero-length phases are skipped so that t stays strictly increasing.
  auto add = [&p](double time, double mm) {
    if (!p.t.empty() && time <= p.t.back()) return;
    p.t.push_back(time);
    p.plate_mm.push_back(mm);
  };
  const double push_s = depth_mm / speed_mm_s;
  add(0.0, 0.0);
  add(push_s, depth_mm);
  add(push_s + hold_s, depth_mm);
  add(2.0 * push_s + hold_s, 0.0);
  add(2.0 * push_s + hold_s + after_s, 0.0);
  return p;
}

}  // namespace rheo
