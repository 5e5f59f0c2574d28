// The bit-true TEM with the parallel Maxwell arm (tem_edge<Fmt, true>) against the double
// edge kernel, and the host conversion of the arm (gamma, k2t, m) with its range checks.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "sim/error.hpp"
#include "sim/mesh.hpp"
#include "tests/hw/tem_kernel_support.hpp"

namespace rheo::hls {
namespace {

using namespace tem_test;

// The bound of the baseline TEM test (tem_kernel_support.hpp) holds for the arm as well:
// its products have 18-bit operands too, and a third one (k2t m) enters T.

TEST(ArmKernel, MatchesTheDoubleKernelWithArmOnRandomEdgesWithinTheQuantisationBound) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), k2_rel(0.1, 2.0), arm_ext(-0.2, 0.2);
  const double dt = 1.0;  // lengths in units, time in steps, force unit = k1
  int checked = 0;
  for (int n = 0; n < 5000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    m.k2 = k2_rel(rng);
    m.c3 = m.k2 * std::pow(10.0, log_c(rng)) * 20.0;  // relaxation time 2..2000 steps
    const RandomEdge e = random_edge(rng);
    const double mx = e.len * arm_ext(rng);
    const MaterialCoefs mc = encode(m, dt);
    TemIn in = e.words(dt);
    in.m = xw(mx);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt, true>(in, mc, &status);
    ASSERT_EQ(status, 0u);

    const EdgeEval<double> ev =
        evaluate_edge<double>(m, e.xs, e.xe, e.vs, e.ve, e.d, e.L, e.len, mx, nullptr, nullptr,
                              dt);  // the semi-implicit step's arm (evaluate_edge)
    const Eigen::Vector3d u = (e.xe - e.xs) / e.len;
    const double dv = (e.ve - e.vs).norm();
    const double c = m.c1 + m.c2 + m.k1 * dt;
    const double t_scale = std::fabs(m.k1 * m.c2 / c * (e.d - e.L)) +
                           std::fabs(m.c2 * (m.c1 + m.k1 * dt) / c + m.k2 * dt) * dv +
                           std::fabs(m.k2 * mx);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(std::ldexp(double(out.f[a]), -Fmt::kFracF), ev.tension * u[a],
                  kCoefRelBound * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double m_ref = mx + dt * ev.mdot;
    const double dm_scale = dv + std::fabs(m.k2 * dt / m.c3 * mx);
    EXPECT_NEAR(std::ldexp(double(out.m), -Fmt::kFracX), m_ref,
                kCoefRelBound * dm_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
    ++checked;
  }
  EXPECT_EQ(checked, 5000);
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
      driver::make_core_image(model, initial_state(model), dt, 1, driver::FormatDesc{},
                              hls::kThreeElementWithArm);
  ASSERT_FALSE(img.materials.empty());
  const EdgeMaterial& m = model.materials[0];
  // The coefficient encoding is checked to 1e-3 relative (core_image.cpp).
  EXPECT_NEAR(driver::decode_coef(img.materials[0].gamma), m.k2 * dt / m.c3,
              1e-3 * m.k2 * dt / m.c3);
  // The arm's spring acts on m + dm: k2 (1 - gamma) on m, k2 added to ct (core_image.cpp).
  const double k2t = m.k2 * (1.0 - m.k2 * dt / m.c3) * img.units.length_m / img.units.force_N;
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
    driver::make_core_image(model, initial_state(model), 1e-3, 1, driver::FormatDesc{},
                              hls::kThreeElementWithArm);
    FAIL() << "expected rheo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gamma"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rheo::hls
