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

long long gather_rows(const ProblemSize& p, int lanes) {
  if (lanes < 1) throw Error("gather_rows: lanes must be >= 1, got " + std::to_string(lanes));
  if (static_cast<int>(p.degree.size()) != p.particles) {
    throw Error("gather_rows: " + p.name + " has " + std::to_string(p.particles) +
                " particles but " + std::to_string(p.degree.size()) + " degrees");
  }
  std::vector<long long> rows(lanes, 0);
  for (int i = 0; i < p.particles; ++i) rows[i % lanes] += std::max(p.degree[i], 1);
  return *std::max_element(rows.begin(), rows.end());
}

long long cycles_per_step(const ProblemSize& p, int lanes, const CycleModel& model) {
  const long long tem_rows = std::max<long long>(ceil_div(p.edges, lanes), 1);
  return tem_rows + model.tem_drain + gather_rows(p, lanes) + model.mpm_drain;
}

int ramb16_for_memory(long long depth, int width) {
  // RAMB16 aspect ratios (depth x width incl. parity bits where the width allows).
  static constexpr int kDepth[] = {16384, 8192, 4096, 2048, 1024, 512};
  static constexpr int kWidth[] = {1, 2, 4, 9, 18, 36};
  long long best = LLONG_MAX;
  for (int i = 0; i < 6; ++i) {
    best = std::min(best, ceil_div(depth, kDepth[i]) * ceil_div(width, kWidth[i]));
  }
  return static_cast<int>(best);
}

int estimate_core_ramb16(const Capacity& c, int lanes) {
  const int index_bits_p = 12, index_bits_m = 4, word = 32, coef = 24;
  // Particle x and p: read by the TEM's two ends and the MPM in every lane.
  const int particle_state = 2 * ramb16_for_memory(c.particles, 3 * word) * 3 * lanes;
  // Home position, 1/m coefficient and flags: read by the MPM of every lane.
  const int particle_const = ramb16_for_memory(c.particles, 3 * word + coef + 2) * lanes;
  // Edge ends, material, L and d: read by the TEM of every lane.
  const int edge_state =
      ramb16_for_memory(c.edges, 2 * index_bits_p + index_bits_m + 2 * word) * lanes;
  // Edge forces: written by the TEM, read by the gather of every lane.
  const int edge_force = ramb16_for_memory(c.edges, 3 * word) * lanes;
  // Gather table: one 31-bit entry per lane and row.
  const int gather = ramb16_for_memory(c.gather, 31);
  return particle_state + particle_const + edge_state + edge_force + gather;
}

}  // namespace rheo::synth
