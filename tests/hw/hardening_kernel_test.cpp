// The bit-true strain hardening (hls::hardening_h, hls::hardened_coefs,
// tem_edge<Fmt, K, D, true>) against the double edge kernel: the worst error of h = H e^2,
// the per-edge coefficients over the strain range (with and without the force-dependent
// damper), the TEM's force and Voigt length, saturation, and the host's range checks.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <string>

#include "sim/error.hpp"
#include "tests/hw/tem_kernel_support.hpp"

namespace rheo::hls {
namespace {

using namespace tem_test;

// Test units: k1 = 1 N/m, lengths in m, forces in N.
EdgeMaterial hardening_material(double c1, double c2, double hardening) {
  EdgeMaterial m;
  m.k1 = 1.0;
  m.c1 = c1;
  m.c2 = c2;
  m.hardening = hardening;
  return m;
}

// The base coefficients (those of the unhardened spring, at c2 = c2_max with the damper; ct
// without the arms' k, which is ka) and the hardening's and damper's own.
MaterialCoefs encode_hardened(const EdgeMaterial& m, double dt) {
  EdgeMaterial base = m;
  base.hardening = 0.0;
  base.nonlinear = false;
  MaterialCoefs mc = encode(base, dt);
  driver::encode_hardening(m, dt, 1.0, 1.0, "material 0: ", mc);
  if (m.nonlinear) driver::encode_damper(m, dt, 1.0, 15.0, "material 0: ", mc);
  return mc;
}

double decoded(const Coef& c) { return driver::decode_coef(c); }

// h = H e^2 with e = (l - L) / L from the words. Its error: 1/L from L rounded to 18 bits
// (2^-17) and the reciprocal (2.5e-5, DamperKernel's bound), l - L and e rounded to 18-bit
// operands (2^-17 each): e within 4.8e-5, e^2 within twice that; e^2 and H rounded to 18 bits
// (2^-17 each): at most 1.12e-4 of h, plus h's own LSB (2^-28).
constexpr double kHRelBound = 1.12e-4;

TEST(HardeningKernel, StrainTermIsWithinItsBoundOverTheStrainRange) {
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> len(0.05, 4.0), strain(-0.6, 2.0), log_h(-2.0, 2.3);
  double worst = 0.0;
  for (int n = 0; n < 20000; ++n) {
    const double H = std::pow(10.0, log_h(rng));
    const std::int64_t L = xw(len(rng));
    const std::int64_t l = xw(std::ldexp(double(L), -Fmt::kFracX) * (1.0 + strain(rng)));
    std::uint32_t status = 0;
    const Coef hk = driver::encode_coef(H, "hardening", 0);
    const std::int64_t h = hardening_h<Fmt>(l, L, hk, &status);
    const double e = double(l - L) / double(L);
    const double want = H * e * e;
    if (want >= std::ldexp(1.0, kHardHBits - kHardFracH)) {
      EXPECT_NE(status, 0u) << "h = " << want << " beyond the word must be flagged";
      continue;
    }
    ASSERT_EQ(status, 0u) << "n " << n;
    const double got = std::ldexp(double(h), -kHardFracH);
    const double err = std::fabs(got - want);
    EXPECT_LE(err, kHRelBound * want + std::ldexp(1.0, -kHardFracH)) << "e " << e << " H " << H;
    if (want > 1e-3) worst = std::max(worst, err / want);
  }
  RecordProperty("h_worst_relative_error", std::to_string(worst));
  std::printf("h = H e^2: worst relative error %.3g (bound %.3g)\n", worst, kHRelBound);
  EXPECT_GT(worst, 1e-6);  // the bound is the arithmetic's, not a test that cannot fail
}

// Each hardened coefficient is the material's (2^-17) times g / s, q / s, g q / s or h q / s:
//   g = 1 + h (h's error, kHRelBound, then 18 bits: 2^-16 at a mantissa of 2^15),
//   s = s_base + s_c2 q + s_k h (s_k's 2^-17 and h's error, on a share of s at most 1),
//   1/s (18-bit operand 2^-17, reciprocal 2.5e-5),
//   up to two factor products and the scaling, each rounded to a mantissa >= 2^15 (2^-16):
// 7.6e-6 + 1.27e-4 + 1.28e-4 + 3.3e-5 + 4.6e-5 = 3.4e-4.
constexpr double kCoefHardRelBound = 3.4e-4;

struct HardenedCase {
  EdgeMaterial m;
  std::int64_t l, L, ds;
};

HardenedCase draw_case(std::mt19937_64& rng, bool damper) {
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), log_h(-1.0, 2.0), strain(-0.5, 1.0),
      len(0.3, 3.0), u(0.0, 1.0), f(0.01, 0.5), log_ratio(0.3, 2.0);
  HardenedCase k;
  // one draw per statement: the order of a call's arguments differs between compilers
  const double c1 = std::pow(10.0, log_c(rng));
  const double c2 = std::pow(10.0, log_c(rng)) * 10.0;
  k.m = hardening_material(c1, c2, std::pow(10.0, log_h(rng)));
  if (damper) {
    k.m.nonlinear = true;
    k.m.f1 = f(rng);
    k.m.f2 = k.m.f1 + f(rng);
    k.m.c2_min = k.m.c2 / std::pow(10.0, log_ratio(rng));
  }
  k.L = xw(len(rng));
  k.l = xw(std::ldexp(double(k.L), -Fmt::kFracX) * (1.0 + strain(rng)));
  // |d - L| up to 1.5 f2 / k1 with the damper (across its fall), else up to 0.5
  const double reach = damper ? 1.5 * k.m.f2 : 0.5;
  const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
  k.ds = xw(sign * u(rng) * reach);
  return k;
}

// The double coefficients of the hardened edge: g from the words' strain, c2 from the
// hardened spring's force (series_viscosity).
struct Expected {
  double alpha, beta, kt, ct, g, c2;
};

Expected expected(const HardenedCase& k, double dt) {
  const EdgeMaterial& m = k.m;
  const double e = double(k.l - k.L) / double(k.L);
  Expected x;
  x.g = 1.0 + m.hardening * e * e;
  const double ds = std::ldexp(double(k.ds), -Fmt::kFracX);
  x.c2 = series_viscosity(m, std::fabs(m.k1 * x.g * ds));
  const double c = m.c1 + x.c2 + m.k1 * x.g * dt;
  x.alpha = m.k1 * x.g * dt / c;
  x.beta = x.c2 / c;
  x.kt = m.k1 * x.g * x.c2 / c;
  x.ct = x.c2 * (m.c1 + m.k1 * x.g * dt) / (c * dt);
  return x;
}

// The damper's z follows g |d - L|, so g's error moves z as d_lo's does (DamperKernel): the
// shares ln(c2_max / c2) and ln(c2_max / c2_min) f1 / (f2 - f1) of q, times g |ds|'s error
// (kHRelBound and the 18-bit operands of h and |ds|, 2^-16) besides zk's and d_lo's 2^-17.
double z_terms(const EdgeMaterial& m, double c2) {
  if (!m.nonlinear) return 0.0;
  return (std::log(m.c2 / c2) + std::log(m.c2 / m.c2_min) * m.f1 / (m.f2 - m.f1)) *
         (std::ldexp(1.0, -17) + kHRelBound + std::ldexp(1.0, -16));
}

void check_coefficients(bool damper, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double dt = 1.0;
  double worst = 0.0;
  int hardened = 0;
  for (int n = 0; n < 4000; ++n) {
    const HardenedCase k = draw_case(rng, damper);
    const MaterialCoefs mc = encode_hardened(k.m, dt);
    std::uint32_t status = 0;
    const DampedCoefs dc = damper ? hardened_coefs<Fmt, true>(k.ds, k.l, k.L, mc, &status)
                                  : hardened_coefs<Fmt, false>(k.ds, k.l, k.L, mc, &status);
    ASSERT_EQ(status, 0u) << "n " << n;
    const Expected x = expected(k, dt);
    if (x.g > 1.1) ++hardened;
    const double bound = kCoefHardRelBound + z_terms(k.m, x.c2);
    const struct {
      double got, want;
      const char* name;
    } pairs[] = {{decoded(dc.alpha), x.alpha, "alpha"},
                 {decoded(dc.beta), x.beta, "beta"},
                 {decoded(dc.kt), x.kt, "kt"},
                 {decoded(dc.ct) + decoded(dc.cth), x.ct, "ct + cth"}};
    for (const auto& p : pairs) {
      const double err = std::fabs(p.got - p.want) / p.want;
      worst = std::max(worst, err);
      EXPECT_LT(err, bound) << p.name << ", case " << n << ": g " << x.g << " c2 " << x.c2;
    }
  }
  std::printf("hardened coefficients%s: worst relative error %.3g\n",
              damper ? " with the damper" : "", worst);
  EXPECT_GT(hardened, 1000);  // most edges are hardened noticeably: g is exercised
}

TEST(HardeningKernel, CoefficientsFollowTheHardenedStiffness) { check_coefficients(false, 53); }

TEST(HardeningKernel, CoefficientsFollowTheHardenedStiffnessWithTheDamper) {
  check_coefficients(true, 59);
}

// The TEM against the double kernel with hardening (l0 = L): the baseline bound with the
// coefficients' error on the terms' magnitudes.
void check_tem(bool damper, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), log_h(-1.0, 2.0), f(0.005, 0.1),
      log_ratio(0.3, 2.0);
  const double dt = 1.0;
  for (int n = 0; n < 3000; ++n) {
    const double c1 = std::pow(10.0, log_c(rng)) * 10.0;
    const double c2_max = std::pow(10.0, log_c(rng)) * 10.0;
    EdgeMaterial m = hardening_material(c1, c2_max, std::pow(10.0, log_h(rng)));
    if (damper) {
      m.nonlinear = true;
      m.f1 = f(rng);
      m.f2 = m.f1 + f(rng);
      m.c2_min = m.c2 / std::pow(10.0, log_ratio(rng));
    }
    const MaterialCoefs mc = encode_hardened(m, dt);
    const RandomEdge e = random_edge(rng);
    const TemIn in = e.words(dt);
    // the reference's l0 is the L word the core reads
    const double l0 = std::ldexp(double(in.L), -Fmt::kFracX);
    std::uint32_t status = 0;
    const TemOut out = damper ? tem_edge<Fmt, 0, true, true>(in, mc, &status)
                              : tem_edge<Fmt, 0, false, true>(in, mc, &status);
    ASSERT_EQ(status, 0u);
    const EdgeEval<double> ev =
        evaluate_edge<double>(m, e.xs, e.xe, e.vs, e.ve, e.d, l0, l0, 0.0, nullptr, nullptr, dt);
    const double strain = (e.len - l0) / l0;
    const double g = 1.0 + m.hardening * strain * strain;
    const double c2 = series_viscosity(m, std::fabs(m.k1 * g * (e.d - l0)));
    const double c = m.c1 + c2 + m.k1 * g * dt;
    const Eigen::Vector3d u = (e.xe - e.xs) / e.len;
    const double dv = (e.ve - e.vs).norm();
    const double t_scale = std::fabs(m.k1 * g * c2 / c * (e.d - l0)) +
                           std::fabs(c2 * (m.c1 + m.k1 * g * dt) / c) * dv;
    const double rel = kCoefHardRelBound + kCoefRelBound + z_terms(m, c2);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(std::ldexp(double(out.f[a]), -Fmt::kFracF), ev.tension * u[a],
                  rel * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double dd_scale = std::fabs(m.k1 * g * dt / c * (e.d - l0)) + std::fabs(c2 / c) * dv;
    EXPECT_NEAR(std::ldexp(double(out.d), -Fmt::kFracX), e.d + dt * ev.ddot,
                rel * dd_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
  }
}

TEST(HardeningKernel, TemMatchesTheDoubleKernelWithHardening) { check_tem(false, 61); }

TEST(HardeningKernel, TemMatchesTheDoubleKernelWithHardeningAndTheDamper) { check_tem(true, 67); }

// H = 0 on the hardening core: g = 1 and s = 1, so the edge computes what the core without
// hardening computes, within the coefficients' rounding.
TEST(HardeningKernel, NoHardeningOnTheHardeningCoreMatchesTheBaselineCore) {
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0);
  for (int n = 0; n < 1000; ++n) {
    const double c1 = std::pow(10.0, log_c(rng)) * 10.0;
    const double c2 = std::pow(10.0, log_c(rng)) * 10.0;
    const EdgeMaterial m = hardening_material(c1, c2, 0.0);
    const MaterialCoefs mc = encode_hardened(m, 1.0);
    const RandomEdge e = random_edge(rng);
    std::uint32_t s0 = 0, s1 = 0;
    const TemOut base = tem_edge<Fmt, 0, false, false>(e.words(1.0), mc, &s0);
    const TemOut hard = tem_edge<Fmt, 0, false, true>(e.words(1.0), mc, &s1);
    ASSERT_EQ(s0 | s1, 0u);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(double(hard.f[a]), double(base.f[a]), 1e-4 * std::fabs(double(base.f[a])) + 8)
          << "edge " << n;
    }
    EXPECT_NEAR(double(hard.d), double(base.d), 1e-4 * std::fabs(double(base.d - e.words(1.0).d)) + 4);
  }
}

// h beyond its word (H e^2 >= 2^12) saturates and raises the TEM flag; just inside it does
// not.
TEST(HardeningKernel, StrainTermBeyondItsWordRaisesTheFlag) {
  const std::int64_t L = xw(1.0), l = xw(2.0);  // e = 1
  std::uint32_t inside = 0, beyond = 0;
  const std::int64_t h_in = hardening_h<Fmt>(l, L, driver::encode_coef(4000.0, "H", 0), &inside);
  const std::int64_t h_out = hardening_h<Fmt>(l, L, driver::encode_coef(5000.0, "H", 0), &beyond);
  EXPECT_EQ(inside, 0u);
  EXPECT_NEAR(std::ldexp(double(h_in), -kHardFracH), 4000.0, 1.0);
  EXPECT_EQ(beyond, std::uint32_t(kStatusTemSaturated));
  EXPECT_EQ(h_out, (std::int64_t(1) << kHardHBits) - 1);
  // a zero or negative L (never written by the host) is flagged as well
  std::uint32_t zero_l = 0;
  EXPECT_EQ(hardening_h<Fmt>(l, 0, driver::encode_coef(1.0, "H", 0), &zero_l), 0);
  EXPECT_EQ(zero_l, std::uint32_t(kStatusTemSaturated));
}

// A hardened coefficient that could outgrow its format is refused by name.
TEST(HardeningKernel, TheHostRefusesAHardenedRangeTheCoreCannotCarry) {
  // c2 / dt = 1e8 N/m in units of 1 N per m (a damper time c2 / k1 of 1e8 steps): kt's
  // limit is far beyond its format, though kt itself (k1 c2 / c, about 1) fits
  const EdgeMaterial m = hardening_material(1.0, 100.0, 10.0);
  MaterialCoefs mc;
  try {
    driver::encode_hardening(m, 1e-6, 1.0, 1.0, "material 2: ", mc);
    FAIL() << "expected an error";
  } catch (const Error& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("material 2"), std::string::npos) << what;
    EXPECT_NE(what.find("strain hardening"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rheo::hls
