// The bit-true TEM against the double edge kernel (sim/edge_kernel.hpp) on random edges:
// same equations, the difference is quantisation only.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/edge_kernel.hpp"

namespace rheo::hls {
namespace {

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

TEST(TemKernel, MatchesTheDoubleKernelOnRandomEdgesWithinTheQuantisationBound) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(0.0, 6.0), vel(-2e-3, 2e-3), strain(-0.2, 0.2),
      log_c(-1.0, 2.0), unit(0.0, 1.0);
  const double dt = 1.0;  // lengths in units, time in steps, force unit = k1
  for (int n = 0; n < 5000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    m.a_min = unit(rng) < 0.5 ? 0.9 : 0.0;
    m.a_max = unit(rng) < 0.5 ? 1.1 : 1e30;
    Eigen::Vector3d xs, xe, vs, ve;
    for (int a = 0; a < 3; ++a) {
      xs[a] = pos(rng);
      xe[a] = pos(rng);
      vs[a] = vel(rng);
      ve[a] = vel(rng);
    }
    const double len = (xe - xs).norm();
    if (len < 0.3) continue;
    const double L = len * (1.0 + strain(rng));
    const double d = L * (1.0 + strain(rng));

    MaterialCoefs mc;
    const double c = m.c1 + m.c2;
    mc.alpha = driver::encode_coef(m.k1 * dt / c, "alpha", S::kAlpha);
    mc.beta = driver::encode_coef(m.c2 / c, "beta", S::kBeta);
    mc.kt = driver::encode_coef(m.k1 * m.c2 / c, "kt", S::kKt);
    mc.ct = driver::encode_coef(m.c1 * m.c2 / (c * dt), "ct", S::kCt);
    if (m.a_min > 0) {
      mc.a_min = driver::encode_coef(m.a_min, "a_min", 0);
      mc.flags |= kClampLowEnable;
    }
    if (m.a_max < 10) {
      mc.a_max = driver::encode_coef(m.a_max, "a_max", 0);
      mc.flags |= kClampHighEnable;
    }
    auto xw = [](double v) { return std::int64_t(std::llround(std::ldexp(v, Fmt::kFracX))); };
    auto pw = [](double v) { return std::int64_t(std::llround(std::ldexp(v, Fmt::kFracP))); };
    TemIn in;
    for (int a = 0; a < 3; ++a) {
      in.xs[a] = xw(xs[a]);
      in.xe[a] = xw(xe[a]);
      in.ps[a] = pw(vs[a] * dt);
      in.pe[a] = pw(ve[a] * dt);
    }
    in.d = xw(d);
    in.L = xw(L);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt>(in, mc, &status);
    ASSERT_EQ(status, 0u);

    const EdgeEval<double> ev = evaluate_edge<double>(m, xs, xe, vs, ve, d, L, len, 0.0);
    const Eigen::Vector3d u = (xe - xs) / len;
    const double d_ref = clamp_voigt_length(m, d + dt * ev.ddot, ev.length);
    const double t_scale =
        std::fabs(m.k1 * m.c2 / c * (d - L)) + std::fabs(m.c1 * m.c2 / c) * (ve - vs).norm();
    for (int a = 0; a < 3; ++a) {
      const double f = std::ldexp(double(out.f[a]), -Fmt::kFracF);
      EXPECT_NEAR(f, ev.tension * u[a],
                  kCoefRelBound * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double dd_scale = std::fabs(dt * ev.ddot) + std::fabs(m.c2 / c) * (ve - vs).norm();
    const bool clamped = d_ref != d + dt * ev.ddot;  // the bound a*l carries a's rounding
    EXPECT_NEAR(std::ldexp(double(out.d), -Fmt::kFracX), d_ref,
                kCoefRelBound * (dd_scale + (clamped ? std::fabs(d_ref) : 0.0)) +
                    kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
  }
}

TEST(TemKernel, ZeroLengthEdgeRaisesTheDegenerateFlagAndNoForce) {
  MaterialCoefs mc;
  mc.kt = driver::encode_coef(0.5, "kt", S::kKt);
  TemIn in{};
  in.d = 1 << 20;
  std::uint32_t status = 0;
  const TemOut out = tem_edge<Fmt>(in, mc, &status);
  EXPECT_TRUE(status & kStatusDegenerateEdge);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(out.f[a], 0);
}

}  // namespace
}  // namespace rheo::hls
