#include "host/synth/performance_model.hpp"

#include <algorithm>
#include <climits>

#include "sim/error.hpp"

namespace rheo::synth {
namespace {
long long ceil_div(long long a, long long b) { return (a + b - 1) / b; }
}  // namespace

int estimate_slices(const Resources& r) {
  return static_cast<int>(ceil_div(std::max(r.lut4, r.ff), 2));
}

Utilisation utilisation(const Resources& r, const Device& device) {
  Utilisation u;
  u.slices = estimate_slices(r);
  u.slices_pct = 100.0 * u.slices / device.slices;
  u.mult18_pct = 100.0 * r.mult18 / device.mult18;
  u.ramb16_pct = 100.0 * r.ramb16 / device.ramb16;
  return u;
}

int lanes_that_fit(const Resources& per_lane, const Resources& shared, const Device& device) {
  const auto fit = [](long long budget, long long shared_use, long long lane_use) {
    if (shared_use > budget) return 0LL;
    if (lane_use <= 0) return static_cast<long long>(INT_MAX);
    return (budget - shared_use) / lane_use;
  };
  long long lanes = fit(device.slices, estimate_slices(shared), estimate_slices(per_lane));
  lanes = std::min(lanes, fit(device.mult18, shared.mult18, per_lane.mult18));
  lanes = std::min(lanes, fit(device.ramb16, shared.ramb16, per_lane.ramb16));
  return static_cast<int>(lanes);
}

long long cycles_per_step(const ProblemSize& p, int lanes, const CycleModel& model) {
  if (lanes < 1) throw Error("cycles_per_step: lanes must be >= 1, got " + std::to_string(lanes));
  const long long tem = ceil_div(p.edges, lanes) + model.tem_latency;
  const long long gather =
      ceil_div(2LL * p.edges + p.particles_without_edges, lanes) + model.mpm_latency;
  return tem + gather + model.overhead;
}

}  // namespace rheo::synth
