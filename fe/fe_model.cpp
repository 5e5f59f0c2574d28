#include "fe/fe_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/error.hpp"

namespace rheo::fe {

namespace {

void check(const char* name, double v, bool zero_ok) {
  if (!std::isfinite(v) || v < 0.0 || (!zero_ok && v == 0.0)) {
    std::ostringstream os;
    os << "plate protocol " << name << " = " << v << ": expected " << (zero_ok ? ">= 0" : "> 0")
       << " and finite";
    throw Error(os.str());
  }
}

}  // namespace

PlateHistory push_hold_release(double push_speed_m_s, double depth_m, double hold_s,
                               double release_speed_m_s, double after_s) {
  check("push_speed_m_s", push_speed_m_s, false);
  check("depth_m", depth_m, false);
  check("hold_s", hold_s, true);
  check("release_speed_m_s", release_speed_m_s, false);
  check("after_s", after_s, true);
  const double t_push = depth_m / push_speed_m_s;
  const double t_hold = t_push + hold_s;
  const double t_release = t_hold + depth_m / release_speed_m_s;
  PlateHistory h;
  h.duration_s = t_release + after_s;
  h.depth_m = [=](double t) {
    if (t <= t_push) return push_speed_m_s * std::max(t, 0.0);
    if (t <= t_hold) return depth_m;
    if (t <= t_release) return depth_m - release_speed_m_s * (t - t_hold);
    return 0.0;
  };
  return h;
}

PlateRecord run_plate_history(ContinuumModel& model, const PlateHistory& history, double dt_s) {
  if (!std::isfinite(dt_s) || !(dt_s > 0.0)) {
    std::ostringstream os;
    os << "time step dt = " << dt_s << " s: expected positive and finite";
    throw Error(os.str());
  }
  if (!history.depth_m) throw Error("plate history: no depth function");
  PlateRecord rec;
  const double t_end = history.duration_s;
  // Steps counted rather than accumulated, so that the record ends on the duration.
  const double t0 = model.time_s();
  const auto n = static_cast<long>(std::ceil((t_end - t0) / dt_s - 1e-9));
  for (long i = 1; i <= n; ++i) {
    // Every step but the last exactly dt, so that the factorisation made for it is reused.
    const double t = i == n ? t_end : t0 + static_cast<double>(i) * dt_s;
    const double step = i == n ? t_end - model.time_s() : dt_s;
    const StepReport r = model.step(step, history.depth_m(t));
    rec.t_s.push_back(r.t_s);
    rec.plate_depth_m.push_back(r.plate_depth_m);
    rec.force_N.push_back(r.force_N);
    rec.top_uz_m.push_back(model.top_vertical_displacement());
    rec.contact_nodes.push_back(r.contact_nodes);
  }
  return rec;
}

}  // namespace rheo::fe
