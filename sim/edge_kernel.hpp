// Stateless per-edge kernel of the three-element rheological edge (docs/model.md),
// written once and templated on the scalar type (double, float, ceres::Jet, ...).
//
//   r = x_e - x_s,  l = |r|,  u = r / l,  ldot = u . (v_e - v_s)
//   ddot = (c2*ldot - k1*(d - L)) / (c1 + c2)      both parts carry the same tension
//   T    = k1*(d - L) + c1*ddot                     T > 0 pulls the ends together
//   force on s: +T*u     force on e: -T*u
//   d <- clamp(d + dt*ddot, a_min*l, a_max*l)       length-ratio constraint (seed 000, eq. 8)
//
// Optional extensions (all off when their coefficients are zero):
//   - force-dependent nonlinear series damper c2(f) (seed 000 §3.3): c2_max below f1,
//     A*exp(-B f) between f1 and f2, c2_min above f2, where f is the Voigt spring force
//     |k1 (d - L)| (equal to the tension at rest; explicit, so no extra state);
//   - strain hardening: k1_eff = k1 * (1 + hardening * e^2), e = (l - l0) / l0;
//   - a parallel Maxwell arm (spring k2 in series with damper c3) between the same
//     particles, with its own state m (the arm spring's extension). It adds a second
//     relaxation time c3/k2 (four-element / generalised Maxwell, seed 002):
//       mdot = ldot - (k2/c3) m,  T += k2 * m.
//   - a relaxation spectrum: up to kMaxSpectrumArms further parallel Maxwell arms
//     (k_j, c_j), each with its own extension state s_j, the same law as the first arm:
//       sdot_j = ldot - (k_j/c_j) s_j,  T += k_j * s_j.
//     A set of arms with log-spaced relaxation times stands for a broad, power-law-like
//     relaxation (a fractional element realised as a Prony series, docs/model.md).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace rheo {

// Coefficients of one edge in SI units (N/m, N s/m, m). Plain data so that every
// backend (reference, bit-true host conversion, fitting) reads the same values.
struct EdgeMaterial {
  double k1 = 0.0;       // Voigt spring stiffness [N/m]
  double c1 = 0.0;       // Voigt damper viscosity [N s/m]
  double c2 = 0.0;       // series damper viscosity [N s/m] (c2_max when nonlinear)
  double a_min = 0.0;    // lower bound of d / l (length-ratio clamp)
  double a_max = 1e30;   // upper bound of d / l
  // Force-dependent nonlinear series damper (off when nonlinear == false).
  bool nonlinear = false;
  double f1 = 0.0;       // [N] below: c2 (= c_max)
  double f2 = 0.0;       // [N] above: c2_min
  double c2_min = 0.0;   // [N s/m]
  // Strain hardening coefficient (dimensionless, 0 = linear spring).
  double hardening = 0.0;
  // Parallel Maxwell arm (off when k2 == 0 or c3 == 0).
  double k2 = 0.0;       // [N/m]
  double c3 = 0.0;       // [N s/m]

  // Relaxation spectrum: further Maxwell arms (spring k [N/m], damper c [N s/m]); the
  // first spectrum_arms entries are used.
  struct Arm {
    double k = 0.0;
    double c = 0.0;
  };
  static constexpr int kMaxSpectrumArms = 8;
  int spectrum_arms = 0;
  std::array<Arm, kMaxSpectrumArms> spectrum{};

  bool has_maxwell_arm() const { return k2 > 0.0 && c3 > 0.0; }
  bool has_spectrum() const { return spectrum_arms > 0; }
};

// Result of evaluating one edge: the tension and the rates of its internal states.
template <typename T>
struct EdgeEval {
  T tension;   // T > 0 pulls the ends together
  T ddot;      // rate of the Voigt length d
  T mdot;      // rate of the Maxwell-arm extension m (0 without the arm)
  T length;    // current edge length l
  T ldot;      // current stretching rate
};

// Series-damper viscosity for a given Voigt spring force magnitude f (seed 000 §3.3).
// Between f1 and f2 the curve A*exp(-B f) passes through (f1, c2) and (f2, c2_min).
template <typename T>
T series_viscosity(const EdgeMaterial& m, const T& f) {
  using std::exp;
  using std::log;
  if (!m.nonlinear || !(m.f2 > m.f1)) return T(m.c2);
  if (f <= T(m.f1)) return T(m.c2);
  if (f >= T(m.f2)) return T(m.c2_min);
  const double b = log(m.c2 / m.c2_min) / (m.f2 - m.f1);
  return T(m.c2) * exp(-T(b) * (f - T(m.f1)));
}

// Evaluates one edge. xs, xe, vs, ve are 3-vectors (Eigen or any type with
// operator[] and size 3); d is the Voigt length, L its natural length, l0 the rest
// length of the whole edge (for strain hardening), mx the Maxwell-arm extension.
// With a relaxation spectrum, spectrum_s points at the material's spectrum_arms extension
// states and spectrum_sdot receives their rates (both may be null without a spectrum).
// lead: the springs of the edge's internal states act with those states advanced by one
// step of length `lead`. 0 gives the differential equation's right-hand side (RK4,
// energies); the semi-implicit Euler step passes dt, so every spring sees the extension
// that goes with the current positions, as the particles' own update does:
//  - the Voigt spring acts on d + dt ddot, which makes the d update backward Euler for the
//    current stretching rate: ddot = (c2 ldot - k1 (d - L)) / (c1 + c2 + k1 dt), and
//    T = c2 (ldot - ddot) = k1 (d + dt ddot - L) + c1 ddot;
//  - an arm spring acts on m + dt mdot (its update stays forward Euler: the hardware's).
// Without the lead a spring lags the motion by one step, which is the explicit (not the
// symplectic) Euler step for it: its oscillation grows by ~ dt^2 k / mass per step and only
// the Voigt damper c1 holds it, which fails once dt is large against c1 / k (mass-scaled
// models with long steps, docs/model.md).
template <typename T, typename V>
EdgeEval<T> evaluate_edge(const EdgeMaterial& m, const V& xs, const V& xe, const V& vs,
                          const V& ve, const T& d, double L, double l0, const T& mx,
                          const T* spectrum_s = nullptr, T* spectrum_sdot = nullptr,
                          double lead = 0.0) {
  using std::sqrt;
  T r[3], dv[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = T(xe[i]) - T(xs[i]);
    dv[i] = T(ve[i]) - T(vs[i]);
  }
  const T l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  const T ldot = (r[0] * dv[0] + r[1] * dv[1] + r[2] * dv[2]) / l;
  T k1 = T(m.k1);
  if (m.hardening != 0.0) {
    const T e = (l - T(l0)) / T(l0);
    k1 = k1 * (T(1.0) + T(m.hardening) * e * e);
  }
  const T spring = k1 * (d - T(L));
  const T abs_spring = spring < T(0.0) ? -spring : spring;
  const T c2 = series_viscosity(m, abs_spring);
  const T ddot = (c2 * ldot - spring) / (T(m.c1) + c2 + k1 * T(lead));
  T tension = spring + (k1 * T(lead) + T(m.c1)) * ddot;
  T mdot = T(0.0);
  if (m.has_maxwell_arm()) {
    mdot = ldot - T(m.k2 / m.c3) * mx;
    tension = tension + T(m.k2) * (mx + T(lead) * mdot);
  }
  if (spectrum_s != nullptr) {
    for (int j = 0; j < m.spectrum_arms; ++j) {
      const EdgeMaterial::Arm& a = m.spectrum[j];
      spectrum_sdot[j] = ldot - T(a.k / a.c) * spectrum_s[j];
      tension = tension + T(a.k) * (spectrum_s[j] + T(lead) * spectrum_sdot[j]);
    }
  }
  return {tension, ddot, mdot, l, ldot};
}

// Length-ratio clamp of the updated Voigt length (seed 000, eq. 8).
template <typename T>
T clamp_voigt_length(const EdgeMaterial& m, const T& d_new, const T& l) {
  const T lo = T(m.a_min) * l;
  const T hi = T(m.a_max) * l;
  if (d_new < lo) return lo;
  if (d_new > hi) return hi;
  return d_new;
}

}  // namespace rheo
