#include "host/synth/performance_model.hpp"

#include <algorithm>
#include <climits>

#include "host/driver/core_image.hpp"
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

ProblemSize problem_size(const std::string& name, const Model& model) {
  ProblemSize p{name, model.num_particles(), model.num_edges(), {}};
  for (const Edge& e : model.edges) p.ends.push_back({e.s, e.e});
  return p;
}

long long edge_rows(const ProblemSize& p, int lanes) {
  if (static_cast<int>(p.ends.size()) != p.edges) {
    throw Error("edge_rows: " + p.name + " has " + std::to_string(p.edges) + " edges but " +
                std::to_string(p.ends.size()) + " end pairs");
  }
  return driver::schedule_edges(p.ends, lanes).rows;
}

ProblemSize lattice_problem(int n1, int n2, int n3) {
  if (n1 < 1 || n2 < 1 || n3 < 1) throw Error("lattice_problem: sizes must be >= 1");
  ProblemSize p{
      std::to_string(n1) + "x" + std::to_string(n2) + "x" + std::to_string(n3) + " lattice",
      n1 * n2 * n3,
      0,
      {}};
  const auto index = [&](int i, int j, int k) { return i + n1 * (j + n2 * k); };
  for (int k = 0; k < n3; ++k)
    for (int j = 0; j < n2; ++j)
      for (int i = 0; i < n1; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || c < 0 || a >= n1 || b >= n2 || c >= n3) continue;
              const int from = index(i, j, k), to = index(a, b, c);
              if (to > from) p.ends.push_back({from, to});  // each pair once
            }
  p.edges = static_cast<int>(p.ends.size());
  return p;
}

long long cycles_per_step(const ProblemSize& p, int lanes, const CycleModel& model) {
  if (lanes < 1) throw Error("cycles_per_step: lanes must be >= 1, got " + std::to_string(lanes));
  return std::max<long long>(edge_rows(p, lanes), 1) + model.tem_drain +
         ceil_div(p.particles, lanes) + model.mpm_drain;
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

Ramb16Breakdown core_ramb16_breakdown(const Capacity& c, int lanes) {
  const int word = 32, coef = 24, flags = 2, material = 4, bank = 4;
  const int sum = 3 * (word + hls::kForceAccGuardBits);
  const long long bank_depth = ceil_div(c.particles, lanes);
  const long long lane_depth = ceil_div(c.edges, lanes);
  int local_bits = 1;
  while ((1LL << local_bits) < bank_depth) ++local_bits;
  // Per bank: x and p (one memory per word: the host writes single words), x0, 1/m,
  // flags, the start and end force sums. Per lane: the slot record {valid, end bank, end
  // local, start local}, L, d, material.
  Ramb16Breakdown b;
  b.position_velocity = lanes * 6 * ramb16_for_memory(bank_depth, word);
  b.home_position = lanes * 3 * ramb16_for_memory(bank_depth, word);
  b.inverse_mass = lanes * ramb16_for_memory(bank_depth, coef);
  b.particle_flags = lanes * ramb16_for_memory(bank_depth, flags);
  b.force_sums = lanes * 2 * ramb16_for_memory(bank_depth, sum);
  b.edge_record = lanes * ramb16_for_memory(lane_depth, 1 + bank + 2 * local_bits);
  b.rest_length = lanes * ramb16_for_memory(lane_depth, word);
  b.voigt_length = lanes * ramb16_for_memory(lane_depth, word);
  b.edge_material = lanes * ramb16_for_memory(lane_depth, material);
  return b;
}

int estimate_core_ramb16(const Capacity& c, int lanes) {
  return core_ramb16_breakdown(c, lanes).total();
}

}  // namespace rheo::synth
