// The bit-true TEM with the parallel Maxwell arm (tem_edge<Fmt, 1>) against the double
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
    in.m[0] = xw(mx);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt, 1>(in, mc, &status);
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
    EXPECT_NEAR(std::ldexp(double(out.m[0]), -Fmt::kFracX), m_ref,
                kCoefRelBound * dm_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
        << "edge " << n;
    ++checked;
  }
  EXPECT_EQ(checked, 5000);
}

// Four arms: the parallel arm (k2, c3) and three spectrum arms, against evaluate_edge with
// the same arms (the relaxation_spectrum cause's model). The bound grows by the arms'
// terms: each arm's product is rounded like the others.
TEST(ArmKernel, FourArmsMatchTheDoubleKernelWithArmAndSpectrumWithinTheQuantisationBound) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), k_rel(0.05, 1.0), arm_ext(-0.2, 0.2);
  const double dt = 1.0;
  for (int n = 0; n < 3000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    m.k2 = k_rel(rng);
    m.c3 = m.k2 * std::pow(10.0, log_c(rng)) * 20.0;
    m.spectrum_arms = 3;
    for (int j = 0; j < 3; ++j) {
      m.spectrum[j].k = k_rel(rng);
      m.spectrum[j].c = m.spectrum[j].k * std::pow(10.0, log_c(rng) + j) * 20.0;  // tau >= 2 steps
    }
    ASSERT_EQ(driver::hardware_arm_count(m), 4);
    const RandomEdge e = random_edge(rng);
    double ext[4];
    for (double& x : ext) x = e.len * arm_ext(rng);
    const MaterialCoefs mc = encode(m, dt);
    TemIn in = e.words(dt);
    for (int j = 0; j < 4; ++j) in.m[j] = xw(ext[j]);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt, 4>(in, mc, &status);
    ASSERT_EQ(status, 0u);

    double sdot[3];
    const EdgeEval<double> ev = evaluate_edge<double>(m, e.xs, e.xe, e.vs, e.ve, e.d, e.L, e.len,
                                                      ext[0], ext + 1, sdot, dt);
    const Eigen::Vector3d u = (e.xe - e.xs) / e.len;
    const double dv = (e.ve - e.vs).norm();
    const double c = m.c1 + m.c2 + m.k1 * dt;
    double arm_k = 0.0, arm_force = 0.0;
    for (int j = 0; j < 4; ++j) {
      arm_k += driver::hardware_arm(m, j).k;
      arm_force += std::fabs(driver::hardware_arm(m, j).k * ext[j]);
    }
    const double t_scale = std::fabs(m.k1 * m.c2 / c * (e.d - e.L)) +
                           std::fabs(m.c2 * (m.c1 + m.k1 * dt) / c + arm_k * dt) * dv + arm_force;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(std::ldexp(double(out.f[a]), -Fmt::kFracF), ev.tension * u[a],
                  kCoefRelBound * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    for (int j = 0; j < 4; ++j) {
      const double rate = j == 0 ? ev.mdot : sdot[j - 1];
      const EdgeMaterial::Arm arm = driver::hardware_arm(m, j);
      const double dm_scale = dv + std::fabs(arm.k * dt / arm.c * ext[j]);
      EXPECT_NEAR(std::ldexp(double(out.m[j]), -Fmt::kFracX), ext[j] + dt * rate,
                  kCoefRelBound * dm_scale + kLengthAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracX))
          << "edge " << n << " arm " << j;
    }
  }
}

// An arm the material does not use (zero coefficients) adds no force: a four-arm core
// computes a one-arm material's words exactly as the one-arm core does.
TEST(ArmKernel, UnusedArmsOfAFourArmCoreLeaveTheOneArmWordsUnchanged) {
  std::mt19937_64 rng(9);
  EdgeMaterial m;
  m.k1 = 1.0;
  m.c1 = 30.0;
  m.c2 = 300.0;
  m.k2 = 0.4;
  m.c3 = 40.0;
  const MaterialCoefs mc = encode(m, 1.0);
  for (int n = 0; n < 1000; ++n) {
    const RandomEdge e = random_edge(rng);
    TemIn in = e.words(1.0);
    in.m[0] = xw(0.05 * e.len);
    std::uint32_t st1 = 0, st4 = 0;
    const TemOut one = tem_edge<Fmt, 1>(in, mc, &st1);
    const TemOut four = tem_edge<Fmt, 4>(in, mc, &st4);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(four.f[a], one.f[a]) << "edge " << n;
    EXPECT_EQ(four.d, one.d);
    EXPECT_EQ(four.m[0], one.m[0]);
    EXPECT_EQ(st4, st1);
  }
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
  mc.gamma[0] = Coef{};
  mc.k2t[0] = Coef{};
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
    std::uint32_t st_base = 0, st_arm = 0;
    const TemOut base = tem_edge<Fmt>(in, mc, &st_base);
    const TemOut arm = tem_edge<Fmt, 1>(in, mc, &st_arm);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(arm.f[a], base.f[a]) << "edge " << n;
    EXPECT_EQ(arm.d, base.d);
    EXPECT_EQ(st_arm, st_base);
  }
}

TEST(ArmKernel, StretchedEdgeArmExtensionDecaysByGammaEachStep) {
  // An edge at rest length with no motion: ldot = 0, so m_n = m_0 (1 - gamma)^n.
  const double gamma = 0.01;
  MaterialCoefs mc;
  mc.gamma[0] = driver::encode_coef(gamma, "gamma", S::kGamma);
  mc.k2t[0] = driver::encode_coef(0.5, "k2t", S::kK2t);
  TemIn in{};
  in.xe[0] = xw(1.0);
  in.d = in.L = xw(1.0);
  const double m0 = 0.1;
  in.m[0] = xw(m0);
  constexpr int kSteps = 200;
  for (int n = 0; n < kSteps; ++n) {
    std::uint32_t status = 0;
    in.m[0] = tem_edge<Fmt, 1>(in, mc, &status).m[0];
    ASSERT_EQ(status, 0u);
  }
  // Rounding of each step's decrement: one X LSB, plus the 18-bit operand of m (2^-17 of m,
  // times gamma) per step.
  const double gamma_coded = driver::decode_coef(mc.gamma[0]);
  const double expected = m0 * std::pow(1.0 - gamma_coded, kSteps);
  EXPECT_NEAR(std::ldexp(double(in.m[0]), -Fmt::kFracX), expected,
              kSteps * (std::ldexp(1.0, -Fmt::kFracX) + std::ldexp(gamma_coded * m0, -17)));
  EXPECT_LT(std::ldexp(double(in.m[0]), -Fmt::kFracX), 0.2 * m0);  // it did decay
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
  EXPECT_NEAR(driver::decode_coef(img.materials[0].gamma[0]), m.k2 * dt / m.c3,
              1e-3 * m.k2 * dt / m.c3);
  // The arm's spring acts on m + dm: k2 (1 - gamma) on m, k2 added to ct (core_image.cpp).
  const double k2t = m.k2 * (1.0 - m.k2 * dt / m.c3) * img.units.length_m / img.units.force_N;
  EXPECT_NEAR(driver::decode_coef(img.materials[0].k2t[0]), k2t, 1e-3 * k2t);
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

Model small_block_with_spectrum(int spectrum_arms, bool parallel_arm) {
  Model model = small_block_with_arm(parallel_arm ? 1e4 : 0.0, parallel_arm ? 5e3 : 0.0);
  EdgeMaterial& m = model.materials[0];
  m.spectrum_arms = spectrum_arms;
  for (int j = 0; j < spectrum_arms; ++j) {
    m.spectrum[j].k = 2e3 * (j + 1);
    m.spectrum[j].c = m.spectrum[j].k * 0.05 * std::pow(2.0, j);  // tau 50 ms .. 6.4 s
  }
  return model;
}

TEST(ArmCoreImage, TheElementFollowsTheArmCountAndKeepsEveryArmItHasRoomFor) {
  const double dt = 1e-3;
  // three spectrum arms and the parallel arm: four, the four-arm core keeps them all
  const Model four = small_block_with_spectrum(3, true);
  EXPECT_EQ(driver::edge_element_for(four), hls::kThreeElementWith4Arms);
  const driver::CoreImage img = driver::make_core_image(
      four, initial_state(four), dt, 1, driver::FormatDesc{}, hls::kThreeElementWith4Arms);
  EXPECT_TRUE(img.dropped_features.empty()) << img.dropped_features.front();
  for (int j = 0; j < 4; ++j) {
    const EdgeMaterial::Arm a = driver::hardware_arm(four.materials[0], j);
    EXPECT_NEAR(driver::decode_coef(img.materials[0].gamma[j]), a.k * dt / a.c, 1e-3 * a.k * dt / a.c)
        << "arm " << j;
  }
  // one arm: the one-arm core; two spectrum arms: the four-arm core (arms 2, 3 unused)
  EXPECT_EQ(driver::edge_element_for(small_block_with_spectrum(0, true)), hls::kThreeElementWithArm);
  EXPECT_EQ(driver::edge_element_for(small_block_with_spectrum(2, false)),
            hls::kThreeElementWith4Arms);
  EXPECT_EQ(driver::edge_element_for(small_block_with_spectrum(0, false)), hls::kThreeElement);
  // five arms: the eight-arm core
  EXPECT_EQ(driver::edge_element_for(small_block_with_spectrum(4, true)),
            hls::kThreeElementWith8Arms);
  // nine arms: more than any core carries; the arms are dropped and said so
  const Model nine = small_block_with_spectrum(8, true);
  std::vector<std::string> dropped;
  const Model hw = driver::hardware_model(nine, &dropped, driver::edge_element_for(nine));
  EXPECT_EQ(hw.materials[0].spectrum_arms, 0);
  EXPECT_FALSE(hw.materials[0].has_maxwell_arm());
  ASSERT_FALSE(dropped.empty());
  EXPECT_NE(dropped.back().find("8 of the 9 Maxwell arms"), std::string::npos) << dropped.back();
}

TEST(ArmCoreImage, ArmExtensionsOfTheStateReachTheirEdgeWordsInTheCoresOrder) {
  const Model model = small_block_with_spectrum(3, true);
  State st = initial_state(model);
  for (int k = 0; k < model.num_edges(); ++k) {
    for (int j = 0; j < 4; ++j) driver::arm_extension(model, st, k, j) = 1e-4 * (j + 1);
  }
  EXPECT_DOUBLE_EQ(st.m[0], 1e-4);
  EXPECT_DOUBLE_EQ(st.spectrum[2], 4e-4);
  const driver::CoreImage img = driver::make_core_image(model, st, 1e-3, 1, driver::FormatDesc{},
                                                        hls::kThreeElementWith4Arms);
  const hls::EdgeEntry& e = img.edges[img.edge_slot[0]];
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(driver::from_x_word(e.m[j], img), 1e-4 * (j + 1), 1e-9) << "arm " << j;
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
