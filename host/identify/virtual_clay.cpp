#include "host/identify/virtual_clay.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "sim/error.hpp"

namespace rheo::identify {

RelaxationArms relaxation_arms(const FourElementB& b) {
  return rheo::relaxation_arms(
      rheo::four_element_law(rheo::FourElementNetwork::kB, {b.E1, b.E2, b.c1, b.c2}));
}

SpecimenParams clay_column_params(const FourElementB& b, double voigt_share) {
  const RelaxationArms arms = relaxation_arms(b);
  SpecimenParams p;
  const double eta = arms.g_slow * arms.tau_slow;
  p.E1 = arms.g_slow;
  p.c1 = voigt_share * eta;
  p.c2 = (1.0 - voigt_share) * eta;
  p.E2 = arms.g_fast;
  p.c3 = arms.g_fast * arms.tau_fast;
  return p;
}

Measurement push_hold_release(const Geometry& g, double depth_mm, double push_speed_mm_s,
                              double hold_s, double release_speed_mm_s, double after_s,
                              double rate_hz) {
  if (!(depth_mm > 0 && push_speed_mm_s > 0 && hold_s >= 0 && release_speed_mm_s > 0 &&
        after_s >= 0 && rate_hz > 0)) {
    throw Error("push_hold_release: expected positive depth, speeds and rate, non-negative times");
  }
  const double t_push = depth_mm / push_speed_mm_s;
  const double t_hold = t_push + hold_s;
  const double t_rel = t_hold + depth_mm / release_speed_mm_s;
  const double t_end = t_rel + after_s;
  Measurement m;
  m.source = "virtual";
  m.geometry = g;
  const long n = static_cast<long>(std::floor(t_end * rate_hz + 1e-9)) + 1;
  for (long i = 0; i < n; ++i) {
    const double t = i / rate_hz;
    double p = 0.0;
    if (t < t_push)
      p = push_speed_mm_s * t;
    else if (t < t_hold)
      p = depth_mm;
    else if (t < t_rel)
      p = depth_mm - release_speed_mm_s * (t - t_hold);
    m.time_s.push_back(t);
    m.plate_mm.push_back(p);
    m.force_N.push_back(0.0);
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  return m;
}

void add_load_cell_noise(Measurement& m, double sigma_N, double resolution_N, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_N);
  for (double& f : m.force_N) {
    f += noise(rng);
    if (resolution_N > 0) f = resolution_N * std::round(f / resolution_N);
  }
}

}  // namespace rheo::identify
