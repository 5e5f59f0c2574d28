// The bit-true force-dependent series damper (hls::damper_coefs, tem_edge<Fmt, K, true>)
// against the double edge kernel: the worst errors of its 2^-f table and reciprocal, the
// per-edge coefficients over the whole force range, the TEM's force and Voigt length, and
// the host's range checks.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <string>

#include "sim/error.hpp"
#include "sim/mesh.hpp"
#include "tests/hw/tem_kernel_support.hpp"

namespace rheo::hls {
namespace {

using namespace tem_test;
constexpr int B = Fmt::kOperandBits;
constexpr Rounding R = Fmt::kRounding;

// The 2^-f table: 65 entries in Q1.16 (rounding 2^-17, up to 1.5e-5 of a value >= 1/2),
// linear interpolation over 1/64 (at most (ln 2 / 64)^2 / 8 = 1.47e-5 of the value), the
// interpolation product rounded (another 1.5e-5): at most 4.5e-5 of 2^-f in all, measured
// over every one of the 2^16 fractions.
TEST(DamperKernel, Exp2TableIsWithinItsBoundForEveryFraction) {
  double worst = 0.0;
  for (std::int64_t z = 0; z < (std::int64_t(1) << kDamperFracZ); ++z) {
    const double q = std::ldexp(double(exp2_neg_frac<B, R>(z)), -(B - 2));
    const double exact = std::exp2(-std::ldexp(double(z), -kDamperFracZ));
    worst = std::max(worst, std::fabs(q - exact) / exact);
  }
  RecordProperty("exp2_worst_relative_error", std::to_string(worst));
  std::printf("2^-f table and interpolation: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, 4.5e-5);
  EXPECT_GT(worst, 1e-6);  // the bound is the table's, not a test that cannot fail
}

// The reciprocal: seed error at most 2^-9 (half a 1/256 interval), squared by the Newton
// step (2^-18), plus the roundings of m y0 and y (2^-17 each): at most 2.5e-5, measured over
// every 18-bit mantissa of m.
TEST(DamperKernel, ReciprocalIsWithinItsBoundForEveryMantissa) {
  double worst = 0.0;
  for (std::int64_t mr = std::int64_t(1) << (B - 2); mr < (std::int64_t(1) << (B - 1)); ++mr) {
    const double y = std::ldexp(double(recip_mantissa<B, R>(mr)), -(B - 2));
    const double exact = 1.0 / std::ldexp(double(mr), -(B - 2));
    worst = std::max(worst, std::fabs(y - exact) / exact);
  }
  std::printf("reciprocal: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, 2.5e-5);
}

// A nonlinear material in the test's units (k1 = 1 N/m, lengths in m, dt = 1 s): c2 falls
// from c2 to c2_min between the spring forces f1 and f2.
EdgeMaterial damper_material(double c1, double c2, double ratio, double f1, double f2) {
  EdgeMaterial m;
  m.k1 = 1.0;
  m.c1 = c1;
  m.c2 = c2;
  m.nonlinear = true;
  m.f1 = f1;
  m.f2 = f2;
  m.c2_min = c2 / ratio;
  return m;
}

MaterialCoefs encode_with_damper(const EdgeMaterial& m, double dt) {
  EdgeMaterial base = m;
  base.nonlinear = false;  // the base coefficients are those at c2 = c2_max
  MaterialCoefs mc = encode(base, dt);
  driver::encode_damper(m, dt, 1.0, 15.0, "material 0: ", mc);
  return mc;
}

// Every per-edge coefficient (alpha / s, beta q / s, kt q / s, ct q / s) against the double
// values at c2(f) = series_viscosity: the 18-bit coefficients (2^-17), q (4.5e-5), 1/s
// (2.5e-5, and s's own rounding) and the two roundings of the scaling, whose mantissas can
// shrink to 2^15 (q and 1/m down to 1/2: 3e-5 each): below 1.5e-4; and z itself: its 18-bit
// slope zk errs by up to 2^-17 of z (ln 2 z 2^-17 of q, z = log2(c2_max / c2) up to 10
// here), and the 18-bit threshold d_lo = f1 / k1 by up to 2^-17 of f1, which moves z by
// zk d_lo 2^-17 (ln(c2_max / c2_min) f1 / (f2 - f1) 2^-17 of q: large when the fall is
// narrow against f1).
TEST(DamperKernel, EdgeCoefficientsFollowTheSeriesViscosityOverTheWholeForceRange) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), log_ratio(0.3, 3.0), f(0.01, 0.5),
      u(0.0, 1.0);
  const double dt = 1.0;
  double worst = 0.0;
  for (int n = 0; n < 3000; ++n) {
    // One declaration per draw: a call's arguments are evaluated in the compiler's order.
    const double f1 = f(rng), c1_draw = std::pow(10.0, log_c(rng)),
                 c2_draw = std::pow(10.0, log_c(rng)) * 10.0,
                 ratio = std::pow(10.0, log_ratio(rng)), f2 = f1 + f(rng);
    const EdgeMaterial m = damper_material(c1_draw, c2_draw, ratio, f1, f2);
    const MaterialCoefs mc = encode_with_damper(m, dt);
    // |d - L| from 0 to 1.5 f2 / k1: below f1, across the fall and above f2
    const double ds = (u(rng) < 0.5 ? -1.0 : 1.0) * u(rng) * 1.5 * m.f2;
    std::uint32_t status = 0;
    const DampedCoefs dc = damper_coefs<Fmt>(xw(ds), mc, &status);
    ASSERT_EQ(status, 0u);
    const double c2 = series_viscosity(m, std::fabs(ds * m.k1));
    const double c = m.c1 + c2 + m.k1 * dt;
    const struct {
      const Coef& got;
      double want;
    } pairs[] = {{dc.alpha, m.k1 * dt / c},
                 {dc.beta, c2 / c},
                 {dc.kt, m.k1 * c2 / c},
                 {dc.ct, c2 * (m.c1 + m.k1 * dt) / (c * dt)}};
    for (const auto& p : pairs) {
      const double err = std::fabs(driver::decode_coef(p.got) - p.want) / p.want;
      worst = std::max(worst, err);
      const double z_terms =
          std::log(m.c2 / c2) + std::log(m.c2 / m.c2_min) * m.f1 / (m.f2 - m.f1);
      EXPECT_LT(err, 1.5e-4 + z_terms * std::ldexp(1.0, -17))
          << "edge " << n << " ds " << ds << " c2 " << c2;
    }
  }
  std::printf("damped coefficients: worst relative error %.3g\n", worst);
}

// The TEM with the damper against the double kernel (semi-implicit step): the baseline
// bound with the coefficients' larger error (2e-4 and the z terms of the test above) on the
// terms' magnitudes at c2(f).
TEST(DamperKernel, TemMatchesTheDoubleKernelWithTheNonlinearDamper) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), log_ratio(0.3, 2.0), f(0.005, 0.1);
  const double dt = 1.0;
  int thinned = 0;
  for (int n = 0; n < 3000; ++n) {
    const double f1 = f(rng), c1_draw = std::pow(10.0, log_c(rng)) * 10.0,
                 c2_draw = std::pow(10.0, log_c(rng)) * 10.0,
                 ratio = std::pow(10.0, log_ratio(rng)),
                 f2 = f1 + f(rng);
    const EdgeMaterial m = damper_material(c1_draw, c2_draw, ratio, f1, f2);
    const MaterialCoefs mc = encode_with_damper(m, dt);
    const RandomEdge e = random_edge(rng);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt, 0, true>(e.words(dt), mc, &status);
    ASSERT_EQ(status, 0u);
    const EdgeEval<double> ev = evaluate_edge<double>(m, e.xs, e.xe, e.vs, e.ve, e.d, e.L,
                                                      e.len, 0.0, nullptr, nullptr, dt);
    const double c2 = series_viscosity(m, std::fabs(m.k1 * (e.d - e.L)));
    if (c2 < m.c2) ++thinned;
    const double c = m.c1 + c2 + m.k1 * dt;
    const Eigen::Vector3d u = (e.xe - e.xs) / e.len;
    const double dv = (e.ve - e.vs).norm();
    const double t_scale = std::fabs(m.k1 * c2 / c * (e.d - e.L)) +
                           std::fabs(c2 * (m.c1 + m.k1 * dt) / c) * dv;
    // the coefficients' bound of the test above, with its z terms for this material
    const double kRel = 2e-4 + kCoefRelBound +
                        (std::log(m.c2 / c2) + std::log(m.c2 / m.c2_min) * m.f1 / (m.f2 - m.f1)) *
                            std::ldexp(1.0, -17);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(std::ldexp(double(out.f[a]), -Fmt::kFracF), ev.tension * u[a],
                  kRel * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double dd_scale = std::fabs(m.k1 * dt / c * (e.d - e.L)) + std::fabs(c2 / c) * dv;
    EXPECT_NEAR(std::ldexp(double(out.d), -Fmt::kFracX), e.d + dt * ev.ddot,
                kRel * dd_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
  }
  // most edges are strained beyond f1: the damper is exercised, not bypassed
  EXPECT_GT(thinned, 1500);
}

// A linear material on the damper core: q = 1 and s = 1 up to the encoding, so the edge
// computes what the core without the damper computes, within the coefficients' rounding.
TEST(DamperKernel, LinearMaterialOnTheDamperCoreMatchesTheBaselineCore) {
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0);
  for (int n = 0; n < 1000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    const MaterialCoefs mc = encode_with_damper(m, 1.0);
    const RandomEdge e = random_edge(rng);
    std::uint32_t s0 = 0, s1 = 0;
    const TemOut base = tem_edge<Fmt, 0, false>(e.words(1.0), mc, &s0);
    const TemOut damped = tem_edge<Fmt, 0, true>(e.words(1.0), mc, &s1);
    ASSERT_EQ(s0 | s1, 0u);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(double(damped.f[a]), double(base.f[a]), 1e-4 * std::fabs(double(base.f[a])) + 8)
          << "edge " << n;
    }
  }
}

// Ranges the core cannot carry are refused by name, not computed wrongly.
TEST(DamperKernel, TheHostRefusesADamperRangeTheCoreCannotCarry) {
  // c2 / c2_min = 1e6 against c1 + k1 dt = 2e-6 of c: s would fall below 2^-16
  const EdgeMaterial m = damper_material(1e-6, 1.0, 1e6, 0.1, 0.2);
  EdgeMaterial base = m;
  base.nonlinear = false;
  MaterialCoefs mc = encode(base, 1e-6);
  try {
    driver::encode_damper(m, 1e-6, 1.0, 15.0, "material 3: ", mc);
    FAIL() << "expected an error";
  } catch (const Error& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("material 3"), std::string::npos) << what;
    EXPECT_NE(what.find("series damper"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rheo::hls
