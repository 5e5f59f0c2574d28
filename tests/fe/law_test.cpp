// Viscoelastic laws: the four-element conversion, the three-element relaxation modulus against
// the network's own equations, the exactness of the recursive arm update, and the pseudo-Lame
// elasticity matrices.
#include "fe/law.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "sim/error.hpp"
#include "tests/fe/error_message.hpp"

namespace rheo::fe {
namespace {

// Seed 002's Table II, identified for network (b).
const FourElementParams kTableII{5.8388e4, 1.2353e5, 2.1091e7, 8.3402e5};

// Stress of a law under the ramp eps(t) = rate t for t <= t_r, then held (closed form of the
// convolution with E(t) = e_inf + sum e_k exp(-t/tau_k) + eta delta(t)).
double ramp_hold_stress(const ViscoelasticLaw& law, double rate, double t_r, double t) {
  const double active = std::min(t, t_r);
  double s = law.equilibrium_modulus_Pa() * rate * active;
  for (const MaxwellArm& a : law.arms()) {
    s += rate * a.modulus_Pa * a.tau_s *
         (std::exp(-(t - active) / a.tau_s) - std::exp(-t / a.tau_s));
  }
  if (t <= t_r) s += law.viscosity_Pa_s() * rate;
  return s;
}

TEST(FeLaw, FourElementNetworkIsTheTwoArmsOfItsRelaxationModulus) {
  const ViscoelasticLaw law = ViscoelasticLaw::four_element(FourElementNetwork::kB, kTableII, 0.35);
  const RelaxationArms ref = relaxation_arms(four_element_law(FourElementNetwork::kB, kTableII));
  EXPECT_TRUE(law.is_fluid());
  ASSERT_EQ(law.arms().size(), 2u);
  EXPECT_EQ(law.viscosity_Pa_s(), 0.0);
  for (double t : {0.0, 1.0, 10.0, 50.0, 200.0, 1000.0}) {
    EXPECT_NEAR(law.relaxation_modulus(t), ref.modulus(t), 1e-12 * ref.modulus(0.0)) << t;
  }
  EXPECT_NEAR(law.relaxation_modulus(0.0), kTableII.E2, 1e-9 * kTableII.E2);  // G(0) = B1 = E2
}

TEST(FeLaw, ThreeElementRelaxationMatchesItsOwnNetwork) {
  // Voigt unit (E1 | c1, strain x) in series with damper c2, under a prescribed strain e(t):
  //   c1 x' + E1 x = s,  s = c2 (e' - x')  =>  x' = (c2 e' - E1 x) / (c1 + c2).
  // RK4 with 1 ms steps (local error ~ (dt/tau)^5, tau = 30 s here) against the closed-form
  // ramp response of the derived arm and damper: agreement to 1e-9 of the peak is rounding.
  const double E1 = 4.0e4, c1 = 3.0e5, c2 = 9.0e5;
  const ViscoelasticLaw law = ViscoelasticLaw::three_element(E1, c1, c2, 0.35);
  EXPECT_TRUE(law.is_fluid());
  EXPECT_NEAR(law.viscosity_Pa_s(), c1 * c2 / (c1 + c2), 1e-9 * c1);
  const double rate = 1e-3, t_r = 20.0, dt = 1e-3;
  double x = 0.0, t = 0.0;
  const auto xdot = [&](double tt, double xx) {
    const double ed = tt < t_r ? rate : 0.0;
    return (c2 * ed - E1 * xx) / (c1 + c2);
  };
  const double peak = ramp_hold_stress(law, rate, t_r, t_r);
  for (double target : {5.0, 20.0, 21.0, 50.0, 200.0, 1000.0}) {
    while (t < target - 1e-9) {
      // Steps land on t_r, so the rate is constant within each.
      const double k1 = xdot(t, x), k2 = xdot(t, x + dt / 2 * k1), k3 = xdot(t, x + dt / 2 * k2),
                   k4 = xdot(t, x + dt * k3);
      x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      t += dt;
    }
    // During the ramp, s = c2 (e' - x'), evaluated just before t_r for the sample at t_r.
    const double ed = target <= t_r ? rate : 0.0;
    const double s = c2 * (ed - (c2 * ed - E1 * x) / (c1 + c2));
    EXPECT_NEAR(s, ramp_hold_stress(law, rate, t_r, target), 1e-9 * peak) << "t = " << target;
  }
}

TEST(FeLaw, RecursiveUpdateIsExactForPiecewiseLinearStrain) {
  // Uneven steps through a ramp and hold: the update reproduces the convolution at every step
  // boundary up to rounding (1e-12 of the peak), at any step size.
  const ViscoelasticLaw law =
      ViscoelasticLaw::from_arms(1.0e3, {{8.0e4, 4.5}, {4.0e4, 530.0}}, 0.3, 2.0e3);
  const double rate = 2e-3, t_r = 10.0;
  std::vector<double> times = {0.0, 0.01, 0.5, 3.0, 10.0, 10.001, 17.0, 100.0, 1500.0};
  std::vector<double> q(law.arms().size(), 0.0);
  double eps = 0.0;
  const double peak = ramp_hold_stress(law, rate, t_r, t_r);
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double dt = times[i] - times[i - 1];
    const StepFactors f = law.step_factors(dt);
    const double e_new = rate * std::min(times[i], t_r);
    double s = law.equilibrium_modulus_Pa() * e_new + f.viscous * (e_new - eps);
    for (std::size_t k = 0; k < q.size(); ++k) {
      q[k] = f.decay[k] * q[k] + f.gain[k] * (e_new - eps);
      s += law.arms()[k].modulus_Pa * q[k];
    }
    eps = e_new;
    EXPECT_NEAR(s, ramp_hold_stress(law, rate, t_r, times[i]), 1e-12 * peak) << times[i];
  }
  // Tiny steps keep their digits (expm1): b -> 1, E_eff -> E(0) + eta/dt.
  const StepFactors tiny = law.step_factors(1e-12);
  EXPECT_NEAR(tiny.gain[0], 1.0, 1e-12);
}

TEST(FeLaw, PseudoLameMatricesGiveYoungsModulusAndPoissonRatio) {
  // Uniaxial stress: the compliance's (z, z) entry is 1/E and (x, z) is -gamma'/E, with the
  // formulation's effective values. Inverses of 3x3/6x6 matrices: 1e-12 is rounding.
  const double g = 0.35;
  {
    const Eigen::MatrixXd S = unit_elasticity(g, Formulation::kPlaneStress).inverse();
    EXPECT_NEAR(S(1, 1), 1.0, 1e-12);
    EXPECT_NEAR(S(0, 1), -g, 1e-12);
    EXPECT_NEAR(S(2, 2), 2.0 * (1.0 + g), 1e-12);
  }
  {
    // Plane strain: E' = E / (1 - g^2), g' = g / (1 - g).
    const Eigen::MatrixXd S = unit_elasticity(g, Formulation::kPlaneStrain).inverse();
    EXPECT_NEAR(S(1, 1), 1.0 - g * g, 1e-12);
    EXPECT_NEAR(-S(0, 1) / S(1, 1), g / (1.0 - g), 1e-12);
  }
  {
    const Eigen::MatrixXd S = unit_elasticity(g, Formulation::kSolid).inverse();
    EXPECT_NEAR(S(2, 2), 1.0, 1e-12);
    EXPECT_NEAR(S(0, 2), -g, 1e-12);
    EXPECT_NEAR(S(1, 2), -g, 1e-12);
    EXPECT_NEAR(S(3, 3), 2.0 * (1.0 + g), 1e-12);
  }
  // Plane stress takes the incompressible limit.
  EXPECT_NO_THROW(unit_elasticity(0.5, Formulation::kPlaneStress));
}

TEST(FeLaw, BadParametersAreNamedWithTheirRange) {
  const auto has = [](const std::string& m, const char* s) {
    return m.find(s) != std::string::npos;
  };
  std::string m = message_of([] { ViscoelasticLaw::elastic(0.0, 0.3); });
  EXPECT_TRUE(has(m, "Young's modulus E = 0") && has(m, "positive")) << m;
  m = message_of([] { ViscoelasticLaw::elastic(1e4, 0.6); });
  EXPECT_TRUE(has(m, "Poisson ratio gamma = 0.6") && has(m, "-1 < gamma <= 0.5")) << m;
  m = message_of([] { ViscoelasticLaw::elastic(1e4, -1.0); });
  EXPECT_TRUE(has(m, "Poisson ratio")) << m;
  m = message_of([] { unit_elasticity(0.5, Formulation::kSolid); });
  EXPECT_TRUE(has(m, "gamma = 0.5") && has(m, "-1 < gamma < 0.5") && has(m, "solid")) << m;
  m = message_of([] { unit_elasticity(0.5, Formulation::kPlaneStrain); });
  EXPECT_TRUE(has(m, "plane strain")) << m;
  m = message_of([] { ViscoelasticLaw::from_arms(0.0, {{-1.0, 2.0}}, 0.3); });
  EXPECT_TRUE(has(m, "arm 0 modulus")) << m;
  m = message_of([] { ViscoelasticLaw::from_arms(0.0, {{1.0, 0.0}}, 0.3); });
  EXPECT_TRUE(has(m, "arm 0 relaxation time tau_k = 0")) << m;
  m = message_of([] { ViscoelasticLaw::from_arms(-1.0, {}, 0.3); });
  EXPECT_TRUE(has(m, "equilibrium modulus")) << m;
  m = message_of([] { ViscoelasticLaw::from_arms(0.0, {}, 0.3); });
  EXPECT_TRUE(has(m, "E(0)")) << m;
  m = message_of([] { ViscoelasticLaw::three_element(4e4, 0.0, 1e5, 0.3); });
  EXPECT_TRUE(has(m, "three-element") && has(m, "c1 = 0")) << m;
  FourElementParams p = kTableII;
  p.E1 = -1.0;
  m = message_of([&] { ViscoelasticLaw::four_element(FourElementNetwork::kB, p, 0.35); });
  EXPECT_TRUE(has(m, "E1 = -1")) << m;
  m = message_of([] { ViscoelasticLaw::elastic(1e4, 0.3).step_factors(0.0); });
  EXPECT_TRUE(has(m, "time step dt = 0")) << m;
}

}  // namespace
}  // namespace rheo::fe
