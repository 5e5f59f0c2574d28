// The bit-true TEM with the parallel Maxwell arm (tem_edge<Fmt, true>) against the double
// edge kernel, and the host conversion of the arm (gamma, k2t, m) with its range checks.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/edge_kernel.hpp"
#include "sim/error.hpp"
#include "sim/mesh.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
using S = CoefShifts<Fmt>;

// As in the baseline TEM test: every product has 18-bit operands (coefficient and operand
// each within 2^-17 of their magnitude), and a force passes through about eight such
// roundings; three products enter T: bound 2^-14 (6.1e-5) of the sum of the magnitudes of
// its terms (the damper's with |dv|, as dp is rounded as a vector), plus a few LSBs.
constexpr double kCoefRelBound = 1.0 / (1 << 14);
constexpr double kForceAbsBoundLsb = 8.0;   // F LSBs
constexpr double kLengthAbsBoundLsb = 4.0;  // X LSBs

std::int64_t xw(double v) { return std::llround(std::ldexp(v, Fmt::kFracX)); }
std::int64_t pw(double v) { return std::llround(std::ldexp(v, Fmt::kFracP)); }

MaterialCoefs encode(const EdgeMaterial& m, double dt) {
  MaterialCoefs mc;
  const double c = m.c1 + m.c2;
  mc.alpha = driver::encode_coef(m.k1 * dt / c, "alpha", S::kAlpha);
  mc.beta = driver::encode_coef(m.c2 / c, "beta", S::kBeta);
  mc.kt = driver::encode_coef(m.k1 * m.c2 / c, "kt", S::kKt);
  mc.ct = driver::encode_coef(m.c1 * m.c2 / (c * dt), "ct", S::kCt);
  mc.gamma = driver::encode_coef(m.k2 * dt / m.c3, "gamma", S::kGamma);
  mc.k2t = driver::encode_coef(m.k2, "k2t", S::kK2t);
  return mc;
}

TEST(ArmKernel, MatchesTheDoubleKernelWithArmOnRandomEdgesWithinTheQuantisationBound) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> pos(0.0, 6.0), vel(-2e-3, 2e-3), strain(-0.2, 0.2),
      log_c(-1.0, 2.0), k2_rel(0.1, 2.0), arm_ext(-0.2, 0.2);
  const double dt = 1.0;  // lengths in units, time in steps, force unit = k1
  int checked = 0;
  for (int n = 0; n < 5000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    m.k2 = k2_rel(rng);
    m.c3 = m.k2 * std::pow(10.0, log_c(rng)) * 20.0;  // relaxation time 2..2000 steps
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
    const double mx = len * arm_ext(rng);
    const MaterialCoefs mc = encode(m, dt);
    TemIn in;
    for (int a = 0; a < 3; ++a) {
      in.xs[a] = xw(xs[a]);
      in.xe[a] = xw(xe[a]);
      in.ps[a] = pw(vs[a] * dt);
      in.pe[a] = pw(ve[a] * dt);
    }
    in.d = xw(d);
    in.L = xw(L);
    in.m = xw(mx);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt, true>(in, mc, &status);
    ASSERT_EQ(status, 0u);

    const EdgeEval<double> ev = evaluate_edge<double>(m, xs, xe, vs, ve, d, L, len, mx);
    const Eigen::Vector3d u = (xe - xs) / len;
    const double t_scale = std::fabs(m.k1 * m.c2 / (m.c1 + m.c2) * (d - L)) +
                           std::fabs(m.c1 * m.c2 / (m.c1 + m.c2)) * (ve - vs).norm() +
                           std::fabs(m.k2 * mx);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(std::ldexp(double(out.f[a]), -Fmt::kFracF), ev.tension * u[a],
                  kCoefRelBound * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double m_ref = mx + dt * ev.mdot;
    const double dm_scale = (ve - vs).norm() + std::fabs(m.k2 * dt / m.c3 * mx);
    EXPECT_NEAR(std::ldexp(double(out.m), -Fmt::kFracX), m_ref,
                kCoefRelBound * dm_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
    ++checked;
  }
  EXPECT_GT(checked, 4000);
}

TEST(ArmKernel, ArmWithZeroExtensionAndCoefficientsGivesTheBaselineWordsExactly) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::int64_t> word(-(std::int64_t(1) << 29), std::int64_t(1) << 29);
  EdgeMaterial m;
  m.k1 = 1.0;
  m.c1 = 30.0;
  m.c2 = 300.0;
  m.k2 = 1.0;  // any arm: its coefficients are zeroed below
  m.c3 = 10.0;
  MaterialCoefs mc = encode(m, 1.0);
  mc.gamma = Coef{};
  mc.k2t = Coef{};
  for (int n = 0; n < 1000; ++n) {
    TemIn in;
    for (int a = 0; a < 3; ++a) {
      in.xs[a] = word(rng);
      in.xe[a] = word(rng);
      in.ps[a] = word(rng) >> 8;
      in.pe[a] = word(rng) >> 8;
    }
    in.d = word(rng);
    in.L = word(rng);
    in.m = 0;
    std::uint32_t st_base = 0, st_arm = 0;
    const TemOut base = tem_edge<Fmt>(in, mc, &st_base);
    const TemOut arm = tem_edge<Fmt, true>(in, mc, &st_arm);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(arm.f[a], base.f[a]) << "edge " << n;
    EXPECT_EQ(arm.d, base.d);
    EXPECT_EQ(st_arm, st_base);
  }
}

TEST(ArmKernel, StretchedEdgeArmExtensionDecaysByGammaEachStep) {
  // An edge at rest length with no motion: ldot = 0, so m_n = m_0 (1 - gamma)^n.
  const double gamma = 0.01;
  MaterialCoefs mc;
  mc.gamma = driver::encode_coef(gamma, "gamma", S::kGamma);
  mc.k2t = driver::encode_coef(0.5, "k2t", S::kK2t);
  TemIn in{};
  in.xe[0] = xw(1.0);
  in.d = in.L = xw(1.0);
  const double m0 = 0.1;
  in.m = xw(m0);
  constexpr int kSteps = 200;
  for (int n = 0; n < kSteps; ++n) {
    std::uint32_t status = 0;
    in.m = tem_edge<Fmt, true>(in, mc, &status).m;
    ASSERT_EQ(status, 0u);
  }
  // Rounding of each step's decrement: one X LSB, plus the 18-bit operand of m (2^-17 of m,
  // times gamma) per step.
  const double gamma_coded = driver::decode_coef(mc.gamma);
  const double expected = m0 * std::pow(1.0 - gamma_coded, kSteps);
  EXPECT_NEAR(std::ldexp(double(in.m), -Fmt::kFracX), expected,
              kSteps * (std::ldexp(1.0, -Fmt::kFracX) + std::ldexp(gamma_coded * m0, -17)));
  EXPECT_LT(std::ldexp(double(in.m), -Fmt::kFracX), 0.2 * m0);  // it did decay
}

Model small_block_with_arm(double k2, double c3) {
  BlockSpec spec;
  spec.nx = spec.ny = spec.nz = 3;
  spec.sx = spec.sy = spec.sz = 0.02;
  spec.material.k1 = 2e4;
  spec.material.c1 = 2e3;
  spec.material.c2 = 2e5;
  spec.material.k2 = k2;
  spec.material.c3 = c3;
  return make_block(spec);
}

TEST(ArmCoreImage, ArmCoreImageCarriesGammaAndK2AndKeepsTheFeature) {
  const Model model = small_block_with_arm(1e4, 5e3);
  const double dt = 1e-3;
  const driver::CoreImage img =
      driver::make_core_image(model, initial_state(model), dt, 1, driver::FormatDesc{}, true);
  ASSERT_FALSE(img.materials.empty());
  const EdgeMaterial& m = model.materials[0];
  // The coefficient encoding is checked to 1e-3 relative (core_image.cpp).
  EXPECT_NEAR(driver::decode_coef(img.materials[0].gamma), m.k2 * dt / m.c3,
              1e-3 * m.k2 * dt / m.c3);
  const double k2t = m.k2 * img.units.length_m / img.units.force_N;
  EXPECT_NEAR(driver::decode_coef(img.materials[0].k2t), k2t, 1e-3 * k2t);
  for (const std::string& f : img.dropped_features)
    EXPECT_EQ(f.find("Maxwell"), std::string::npos) << f;
  // The frames carry the arm's regions only for an arm core.
  const driver::CoreImage base = driver::make_core_image(model, initial_state(model), dt, 1);
  EXPECT_GT(driver::image_frames(img).size(), driver::image_frames(base).size());
  bool dropped = false;
  for (const std::string& f : base.dropped_features)
    dropped = dropped || f.find("Maxwell") != std::string::npos;
  EXPECT_TRUE(dropped);
}

TEST(ArmCoreImage, ArmFasterThanOneStepIsRefusedWithTheMaterialNamed) {
  const Model model = small_block_with_arm(1e4, 1.0);  // c3/k2 = 0.1 ms < dt
  try {
    driver::make_core_image(model, initial_state(model), 1e-3, 1, driver::FormatDesc{}, true);
    FAIL() << "expected rheo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gamma"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rheo::hls
