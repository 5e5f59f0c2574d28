#include "sim/relaxation_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sim/error.hpp"

namespace rheo {
namespace {

// Cells reach a third of a window's lower end below it and three times its upper end
// above it, so the cut-off of the series lies outside the window.
constexpr double kBelow = 3.0;
constexpr double kAbove = 3.0;
// The tail arm sits this far above the slowest cell: inside the window it barely relaxes.
constexpr double kTailFactor = 100.0;

}  // namespace

double PowerLawSpectrum::t_mid() const { return std::sqrt(t_lo * t_hi); }

void set_power_law_spectrum(EdgeMaterial& m, const PowerLawSpectrum& s) {
  if (!(s.alpha > 0.0 && s.alpha < 1.0)) {
    throw Error("relaxation spectrum: alpha = " + std::to_string(s.alpha) +
                ", expected a power-law exponent between 0 and 1");
  }
  if (!(s.modulus > 0.0) || !std::isfinite(s.modulus)) {
    throw Error("relaxation spectrum: modulus = " + std::to_string(s.modulus) +
                ", expected a finite value > 0");
  }
  if (!(s.t_lo > 0.0 && s.t_hi > s.t_lo) || !std::isfinite(s.t_hi)) {
    throw Error("relaxation spectrum: window [" + std::to_string(s.t_lo) + ", " +
                std::to_string(s.t_hi) + "] s, expected 0 < t_lo < t_hi");
  }
  const int cells = EdgeMaterial::kMaxSpectrumArms - 1;
  const double tau_lo = s.t_lo / kBelow, tau_hi = s.t_hi * kAbove;
  const double step = std::log(tau_hi / tau_lo) / (cells - 1);  // cell width in ln(tau)
  const double a = s.alpha;
  // H(tau) = amplitude * tau^-alpha per unit ln(tau).
  const double amplitude = s.modulus * std::pow(s.t_mid(), a) / std::tgamma(a);
  m.spectrum_arms = EdgeMaterial::kMaxSpectrumArms;
  for (int j = 0; j < cells; ++j) {
    const double tau = tau_lo * std::exp(step * j);
    // Integral of tau^-alpha over [tau e^(-step/2), tau e^(step/2)] in ln(tau).
    const double k = amplitude * std::pow(tau, -a) * 2.0 * std::sinh(0.5 * a * step) / a;
    m.spectrum[j] = {k, k * tau};
  }
  // Everything above the last cell: integral of tau^-alpha from its upper edge to infinity.
  const double edge = tau_hi * std::exp(0.5 * step);
  const double k_tail = amplitude * std::pow(edge, -a) / a;
  m.spectrum[cells] = {k_tail, k_tail * tau_hi * kTailFactor};
}

double spectrum_relaxation(const EdgeMaterial& m, double t) {
  double g = 0.0;
  for (int j = 0; j < m.spectrum_arms; ++j) {
    g += m.spectrum[j].k * std::exp(-t * m.spectrum[j].k / m.spectrum[j].c);
  }
  return g;
}

double power_law_relaxation(const PowerLawSpectrum& s, double t) {
  return s.modulus * std::pow(t / s.t_mid(), -s.alpha);
}

double fastest_spectrum_time(const EdgeMaterial& m) {
  double tau = std::numeric_limits<double>::infinity();
  for (int j = 0; j < m.spectrum_arms; ++j) tau = std::min(tau, m.spectrum[j].c / m.spectrum[j].k);
  return tau;
}

}  // namespace rheo
