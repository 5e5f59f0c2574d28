// A broad, power-law-like relaxation realised by parallel Maxwell arms (a Prony series).
//
// A fractional (power-law) element relaxes as G(t) = G_mid (t / t_mid)^-alpha, 0 < alpha < 1:
// every decade of time holds about the same share of the relaxation. Its relaxation
// spectrum is continuous, H(tau) = G_mid t_mid^alpha tau^-alpha / Gamma(alpha) per unit
// ln(tau), so G(t) = integral of H(tau) e^(-t/tau) d ln(tau). The edge kernel holds at most
// EdgeMaterial::kMaxSpectrumArms arms, so the spectrum is cut into cells:
//  - arms 1..K-1 at log-spaced times from t_lo/3 to 3 t_hi, each carrying the integral of H
//    over its cell (one cell per arm in ln(tau));
//  - a last arm at 100 times the slowest of these carries the whole tail above it, which
//    inside the window acts as a nearly constant modulus.
// Inside the window [t_lo, t_hi] the arms then follow the power law within a few per cent
// (alpha 0.1: ~1 %, alpha 0.9: ~7-14 %, over 2.5-4 decades; measured by
// tests/sim/relaxation_spectrum_test.cpp and documented in docs/model.md). Outside the window
// the series is not a power law: it tends to a constant below t_lo and decays beyond the
// slowest arm.
#pragma once

#include "sim/edge_kernel.hpp"

namespace rheo {

struct PowerLawSpectrum {
  double modulus = 0.0;  // G(t_mid) [Pa or N/m: the unit of the arms' k]
  double alpha = 0.5;    // power-law exponent, in (0, 1)
  double t_lo = 0.0;     // window of times where the power law should hold [s], 0 < t_lo < t_hi
  double t_hi = 0.0;
  double t_mid() const;  // sqrt(t_lo t_hi), where G equals `modulus`
};

// Replaces the spectrum arms of m by the power law's Prony series (all
// EdgeMaterial::kMaxSpectrumArms arms; c_j = k_j tau_j). Throws rheo::Error when alpha is
// outside (0, 1), the modulus is not positive or the window is empty.
void set_power_law_spectrum(EdgeMaterial& m, const PowerLawSpectrum& s);

// Relaxation modulus of the spectrum arms alone: sum of k_j exp(-t k_j / c_j).
double spectrum_relaxation(const EdgeMaterial& m, double t);

// The power law the series stands for, G_mid (t / t_mid)^-alpha.
double power_law_relaxation(const PowerLawSpectrum& s, double t);

// Shortest relaxation time of the spectrum arms [s] (infinity without arms).
double fastest_spectrum_time(const EdgeMaterial& m);

}  // namespace rheo
