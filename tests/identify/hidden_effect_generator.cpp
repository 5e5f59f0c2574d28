#include "tests/identify/hidden_effect_generator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <random>

namespace rheo::testing {
namespace {

// RK4 step of the body, far below every time constant of the bodies drawn (>= 0.2 s).
constexpr double kStepS = 0.002;

// States: compressive strain eps, Voigt strain ev, Maxwell-arm stress sm, lagged reading y.
using S = std::array<double, 4>;

double series_viscosity(const LumpedBody& b, double spring_stress) {
  if (b.damping_ratio <= 1.0 || b.damping_stress <= 0.0) return b.eta2;
  const double s = std::abs(spring_stress);
  if (s >= b.damping_stress) return b.eta2 / b.damping_ratio;
  return b.eta2 * std::exp(-std::log(b.damping_ratio) * s / b.damping_stress);
}

double modulus(const LumpedBody& b, double eps) { return b.E * (1.0 + b.hardening * eps * eps); }

// Stress of the three-element part for a given strain rate (compression positive):
// sigma3 = E ev + eta1 (epsdot - sigma3/eta2)  =>  sigma3 = (E ev + eta1 epsdot) eta2/(eta1+eta2).
double sigma3(const LumpedBody& b, const S& s, double epsdot) {
  const double spring = modulus(b, s[0]) * s[1];
  const double eta2 = series_viscosity(b, spring);
  return (spring + b.eta1 * epsdot) * eta2 / (b.eta1 + eta2);
}

// Strain rate with zero total stress (plate off the body).
double free_rate(const LumpedBody& b, const S& s) {
  const double spring = modulus(b, s[0]) * s[1];
  const double eta2 = series_viscosity(b, spring);
  return (-s[2] * (b.eta1 + eta2) / eta2 - spring) / b.eta1;
}

S rates(const LumpedBody& b, const S& s, double epsdot, double area) {
  const double sig3 = sigma3(b, s, epsdot);
  const double spring = modulus(b, s[0]) * s[1];
  const double eta2 = series_viscosity(b, spring);
  S r{};
  r[0] = epsdot;
  r[1] = epsdot - sig3 / eta2;
  r[2] = b.E_arm > 0 ? b.E_arm * epsdot - s[2] * b.E_arm / b.eta_arm : 0.0;
  const double force = (sig3 + s[2]) * area;
  r[3] = b.lag_s > 0 ? (force - s[3]) / b.lag_s : 0.0;
  return r;
}

S add(const S& a, const S& k, double f) {
  S o;
  for (int i = 0; i < 4; ++i) o[i] = a[i] + f * k[i];
  return o;
}

}  // namespace

std::string expected_cause(HiddenEffect e) {
  switch (e) {
    case HiddenEffect::kNone:
      return "none";
    case HiddenEffect::kSecondRelaxation:
      return "second_relaxation_time";
    case HiddenEffect::kForceDamping:
      return "force_dependent_damping";
    case HiddenEffect::kHardening:
      return "strain_hardening";
    case HiddenEffect::kLag:
      return "sensor_lag";
    case HiddenEffect::kOffset:
      return "sensor_offset";
  }
  return "none";
}

Record run_lumped(const LumpedBody& b, const Protocol& p, double noise_N, std::uint32_t seed) {
  const double h = b.height_mm, area = b.width_mm * b.depth_mm * 1e-6;
  const double t_push = p.depth_mm / p.push_mm_s, t_hold = t_push + p.hold_s;
  const double t_rel = t_hold + p.depth_mm / p.release_mm_s, t_end = t_rel + p.after_s;
  auto plate = [&](double t) {
    if (t < t_push) return p.push_mm_s * t;
    if (t < t_hold) return p.depth_mm;
    if (t < t_rel) return p.depth_mm - p.release_mm_s * (t - t_hold);
    return 0.0;
  };
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_N);
  Record r;
  S s{0, 0, 0, 0};
  bool contact = false;
  double t = 0.0;
  const double sample_dt = 1.0 / p.rate_hz;
  double next_sample = 0.0;
  double force = 0.0;
  while (t <= t_end + 1e-9) {
    if (t >= next_sample - 1e-9) {
      const double reading = (b.lag_s > 0 ? s[3] : force) + b.offset_N + noise(rng);
      r.t.push_back(next_sample);
      r.plate_mm.push_back(plate(next_sample));
      r.force_N.push_back(reading);
      next_sample += sample_dt;
    }
    const double eps_plate_next = plate(t + kStepS) / h;
    const double epsdot_plate = (eps_plate_next - plate(t) / h) / kStepS;
    // Contact while following the plate needs compression; else move free; the plate
    // catches the body when the free surface would pass it.
    bool use_contact = contact && sigma3(*&b, s, epsdot_plate) + s[2] >= 0.0;
    if (!use_contact) {
      const double free_eps_next = s[0] + kStepS * free_rate(b, s);
      use_contact = eps_plate_next > free_eps_next;
    }
    contact = use_contact;
    auto f = [&](const S& x) {
      const double epsdot = contact ? epsdot_plate : free_rate(b, x);
      return rates(b, x, epsdot, area);
    };
    const S k1 = f(s), k2 = f(add(s, k1, kStepS / 2)), k3 = f(add(s, k2, kStepS / 2)),
            k4 = f(add(s, k3, kStepS));
    for (int i = 0; i < 4; ++i) s[i] += kStepS / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    if (contact) s[0] = eps_plate_next;
    force = contact ? (sigma3(b, s, epsdot_plate) + s[2]) * area : 0.0;
    if (b.lag_s <= 0) s[3] = force;
    t += kStepS;
  }
  return r;
}

void write_csv(const std::string& path, const LumpedBody& b, const Record& r) {
  std::ofstream out(path);
  out << "# rheo-measurement: 1\n# specimen_height_mm: " << b.height_mm
      << "\n# specimen_width_mm: " << b.width_mm << "\n# specimen_depth_mm: " << b.depth_mm
      << "\n# SYNTHETIC: hidden-effect test data\ntime_s,plate_mm,force_N,surface_mm\n";
  out.precision(10);
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    out << r.t[i] << ',' << r.plate_mm[i] << ',' << r.force_N[i] << ",\n";
  }
}

LumpedBody body_for(HiddenEffect e, std::uint32_t seed) {
  std::mt19937 rng(seed * 7919u + 17u);
  std::uniform_real_distribution<double> jitter(0.8, 1.25);
  LumpedBody b;
  b.E *= jitter(rng);
  b.eta1 *= jitter(rng);
  b.eta2 *= jitter(rng);
  switch (e) {
    case HiddenEffect::kNone:
      break;
    case HiddenEffect::kSecondRelaxation:
      b.E_arm = 0.6 * b.E * jitter(rng);
      b.eta_arm = b.E_arm * 1.0 * jitter(rng);  // relaxation time about 1 s
      break;
    case HiddenEffect::kForceDamping:
      b.damping_stress = 5e3 * jitter(rng);
      b.damping_ratio = 10.0 * jitter(rng);
      break;
    case HiddenEffect::kHardening:
      b.hardening = 4.0 * jitter(rng);
      break;
    case HiddenEffect::kLag:
      b.lag_s = 0.4 * jitter(rng);
      break;
    case HiddenEffect::kOffset:
      b.offset_N = 0.06 * jitter(rng);
      break;
  }
  return b;
}

}  // namespace rheo::testing
