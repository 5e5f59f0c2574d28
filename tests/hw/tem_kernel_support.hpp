// Shared by the tests of the bit-true TEM against the double edge kernel
// (tem_kernel_test.cpp, arm_kernel_test.cpp): the quantisation bound, the word conversions,
// the material encoding and the random edge geometry.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/edge_kernel.hpp"

namespace rheo::hls::tem_test {

using Fmt = HardwareFormat;
using S = CoefShifts<Fmt>;

// Every product has 18-bit operands, each rounded to 2^-17 of its block's largest
// magnitude: a force passes through about eight such roundings (coefficient, ds^ or ldot^,
// r^ and the rsqrt (2^-16.4), u, dp^ with the shared exponent of dp, T^, u again), so the
// bound is 2^-14 (6.1e-5) of the terms' magnitudes, where the damper term is taken with
// |dv| rather than |u.dv| (dp^ is rounded relative to the whole vector), plus a few LSBs.
constexpr double kCoefRelBound = 1.0 / (1 << 14);
constexpr double kForceAbsBoundLsb = 8.0;   // F LSBs
constexpr double kLengthAbsBoundLsb = 4.0;  // X LSBs

inline std::int64_t xw(double v) { return std::llround(std::ldexp(v, Fmt::kFracX)); }
inline std::int64_t pw(double v) { return std::llround(std::ldexp(v, Fmt::kFracP)); }

// The coefficients the host sends for material m at time step dt (clamps and the arms'
// gamma and k2t only when the material has them; its arms in the core's order,
// driver::hardware_arm).
inline MaterialCoefs encode(const EdgeMaterial& m, double dt) {
  MaterialCoefs mc;
  const double c = m.c1 + m.c2 + m.k1 * dt;  // the Voigt spring on the updated d
  mc.alpha = driver::encode_coef(m.k1 * dt / c, "alpha", S::kAlpha);
  mc.beta = driver::encode_coef(m.c2 / c, "beta", S::kBeta);
  mc.kt = driver::encode_coef(m.k1 * m.c2 / c, "kt", S::kKt);
  // Each arm's spring acts on m + dm (driver::make_core_image folds it the same way).
  const int arms = driver::hardware_arm_count(m);
  double arm_k = 0.0;
  for (int j = 0; j < arms; ++j) arm_k += driver::hardware_arm(m, j).k;
  mc.ct = driver::encode_coef(m.c2 * (m.c1 + m.k1 * dt) / (c * dt) + arm_k, "ct", S::kCt);
  if (m.a_min > 0) {
    mc.a_min = driver::encode_coef(m.a_min, "a_min", 0);
    mc.flags |= kClampLowEnable;
  }
  if (m.a_max < 10) {
    mc.a_max = driver::encode_coef(m.a_max, "a_max", 0);
    mc.flags |= kClampHighEnable;
  }
  for (int j = 0; j < arms; ++j) {
    const EdgeMaterial::Arm a = driver::hardware_arm(m, j);
    const double gamma = a.k * dt / a.c;
    mc.gamma[j] = driver::encode_coef(gamma, "gamma", S::kGamma);
    mc.k2t[j] = driver::encode_coef(a.k * (1.0 - gamma), "k2t", S::kK2t);
  }
  return mc;
}

// A random edge in a 6-unit box: end points, velocities, the current length len (at least
// 0.3), a rest length L and a Voigt length d each within 20 % of the previous one.
struct RandomEdge {
  Eigen::Vector3d xs, xe, vs, ve;
  double len = 0.0, L = 0.0, d = 0.0;

  // The TEM's input words for this edge (momenta as velocity x dt; the arm's m is 0).
  TemIn words(double dt) const {
    TemIn in;
    for (int a = 0; a < 3; ++a) {
      in.xs[a] = xw(xs[a]);
      in.xe[a] = xw(xe[a]);
      in.ps[a] = pw(vs[a] * dt);
      in.pe[a] = pw(ve[a] * dt);
    }
    in.d = xw(d);
    in.L = xw(L);
    return in;
  }
};

// Draws edges until one is at least 0.3 long.
inline RandomEdge random_edge(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(0.0, 6.0), vel(-2e-3, 2e-3), strain(-0.2, 0.2);
  RandomEdge e;
  do {
    for (int a = 0; a < 3; ++a) {
      e.xs[a] = pos(rng);
      e.xe[a] = pos(rng);
      e.vs[a] = vel(rng);
      e.ve[a] = vel(rng);
    }
    e.len = (e.xe - e.xs).norm();
  } while (e.len < 0.3);
  e.L = e.len * (1.0 + strain(rng));
  e.d = e.L * (1.0 + strain(rng));
  return e;
}

}  // namespace rheo::hls::tem_test
