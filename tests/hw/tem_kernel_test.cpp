// The bit-true TEM against the double edge kernel (sim/edge_kernel.hpp) on random edges:
// same equations, the difference is quantisation only.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "tests/hw/tem_kernel_support.hpp"

namespace rheo::hls {
namespace {

using namespace tem_test;

TEST(TemKernel, MatchesTheDoubleKernelOnRandomEdgesWithinTheQuantisationBound) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> log_c(-1.0, 2.0), unit(0.0, 1.0);
  const double dt = 1.0;  // lengths in units, time in steps, force unit = k1
  for (int n = 0; n < 5000; ++n) {
    EdgeMaterial m;
    m.k1 = 1.0;
    m.c1 = std::pow(10.0, log_c(rng)) * 10.0;
    m.c2 = std::pow(10.0, log_c(rng)) * 10.0;
    m.a_min = unit(rng) < 0.5 ? 0.9 : 0.0;
    m.a_max = unit(rng) < 0.5 ? 1.1 : 1e30;
    const RandomEdge e = random_edge(rng);
    const MaterialCoefs mc = encode(m, dt);
    std::uint32_t status = 0;
    const TemOut out = tem_edge<Fmt>(e.words(dt), mc, &status);
    ASSERT_EQ(status, 0u);

    const EdgeEval<double> ev =
        evaluate_edge<double>(m, e.xs, e.xe, e.vs, e.ve, e.d, e.L, e.len, 0.0, nullptr, nullptr,
                              dt);  // the semi-implicit step's edge (evaluate_edge's lead)
    const Eigen::Vector3d u = (e.xe - e.xs) / e.len;
    const double d_ref = clamp_voigt_length(m, e.d + dt * ev.ddot, ev.length);
    const double c = m.c1 + m.c2 + m.k1 * dt;
    const double dv = (e.ve - e.vs).norm();
    const double t_scale =
        std::fabs(m.k1 * m.c2 / c * (e.d - e.L)) + std::fabs(m.c2 * (m.c1 + m.k1 * dt) / c) * dv;
    for (int a = 0; a < 3; ++a) {
      const double f = std::ldexp(double(out.f[a]), -Fmt::kFracF);
      EXPECT_NEAR(f, ev.tension * u[a],
                  kCoefRelBound * t_scale + kForceAbsBoundLsb * std::ldexp(1.0, -Fmt::kFracF))
          << "edge " << n << " component " << a;
    }
    const double dd_scale = std::fabs(dt * ev.ddot) + std::fabs(m.c2 / c) * dv;
    const bool clamped = d_ref != e.d + dt * ev.ddot;  // the bound a*l carries a's rounding
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
