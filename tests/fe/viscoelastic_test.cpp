// Viscoelastic checks of the continuum model under a sliding floor and a frictionless plate
// (homogeneous uniaxial stress, so the plate force is area x the 1-D stress response): relaxation
// after a fast step, a constant-rate ramp against an independent quadrature of the convolution
// integral, second-order convergence in the time step for a smooth plate history, and the same
// relaxation on tetrahedra.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <functional>
#include <vector>

#include "fe/fe_model.hpp"

namespace rheo::fe {
namespace {

constexpr double kW = 0.08, kH = 0.08, kT = 0.0125, kGamma = 0.35;  // seed 002's specimen
// Seed 002's Table II (network b): 83.19 kPa relaxing in 4.566 s and 40.34 kPa in 534.1 s.
const FourElementParams kTableII{5.8388e4, 1.2353e5, 2.1091e7, 8.3402e5};

ViscoelasticLaw network_b() {
  return ViscoelasticLaw::four_element(FourElementNetwork::kB, kTableII, kGamma);
}
ViscoelasticLaw three_element() { return ViscoelasticLaw::three_element(4.0e4, 2.2e4, 2.2e6, kGamma); }

ModelOptions sliding() {
  ModelOptions opt;
  opt.thickness_m = kT;
  opt.floor = FloorCondition::kSliding;
  opt.contact = PlateContact::kFrictionless;
  return opt;
}

std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", v);
  return buf;
}

// Stress under eps(s) = rate s for s <= t_r then held, in closed form, for E(t) written out
// from the law's arms and damper (sum e_k tau_k (exp(-(t - min(t, t_r))/tau_k) - exp(-t/tau_k)),
// plus eta rate while the ramp lasts).
double ramp_stress(const ViscoelasticLaw& law, double rate, double t_r, double t) {
  const double a = std::min(t, t_r);
  double s = law.equilibrium_modulus_Pa() * rate * a;
  for (const MaxwellArm& arm : law.arms()) {
    s += rate * arm.modulus_Pa * arm.tau_s *
         (std::exp(-(t - a) / arm.tau_s) - std::exp(-t / arm.tau_s));
  }
  if (t <= t_r) s += law.viscosity_Pa_s() * rate;
  return s;
}

// Composite Simpson over [0, min(t, t_end)] of E(t - s) eps'(s) ds for a strain rate
// function, with n intervals, plus eta eps'(t): the convolution integral, independent of the
// recursive update.
double convolution(const ViscoelasticLaw& law, const std::function<double(double)>& rate,
                   double t_end, double t, int n) {
  const double b = std::min(t, t_end);
  const double h = b / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double s = i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += w * law.relaxation_modulus(t - s) * rate(s);
  }
  return sum * h / 3.0 + (t <= t_end ? law.viscosity_Pa_s() * rate(t) : 0.0);
}

// Step to `strain` over t_r, then hold, sampling the force at t_r + each of `after`.
void expect_step_relaxation(const Mesh& mesh, ModelOptions opt, const ViscoelasticLaw& law,
                            double area) {
  ContinuumModel model(mesh, law, opt);
  const double strain = 0.05, t_r = 0.01;
  model.step(t_r, strain * mesh.height_m);
  const double rate = strain / t_r;
  double worst = 0.0;
  const double peak = area * ramp_stress(law, rate, t_r, t_r);
  for (double after : {0.0, 1.0, 10.0, 50.0, 200.0, 1000.0}) {
    // Hold steps of 0.5 s up to 50 s, then larger: the update is exact for any step.
    while (model.time_s() < t_r + after - 1e-9) {
      const double left = t_r + after - model.time_s();
      model.step(std::min(left, model.time_s() < 50.0 ? 0.5 : 25.0), strain * mesh.height_m);
    }
    const double expected = area * ramp_stress(law, rate, t_r, t_r + after);
    // For the four-element (b) law the 10 ms ramp is a step: E(t) itself, to 0.2 %.
    if (law.viscosity_Pa_s() == 0.0) {
      EXPECT_NEAR(model.plate_force_N(), area * strain * law.relaxation_modulus(after),
                  2e-3 * peak) << after;
    }
    worst = std::max(worst, std::abs(model.plate_force_N() - expected) / peak);
  }
  // Exact update and a homogeneous field: only rounding of the solves (~1e-14) accumulates over
  // ~150 steps; 1e-10 of the peak force (measured 8.4e-13).
  EXPECT_LT(worst, 1e-10);
  ::testing::Test::RecordProperty("worst_relative_error", sci(worst));
}

TEST(FeViscoelastic, StepAndHoldRelaxesAsTheRelaxationModulusFourElementB) {
  expect_step_relaxation(make_rectangle(kW, kH, 4, 4), sliding(), network_b(), kW * kT);
}

TEST(FeViscoelastic, StepAndHoldRelaxesAsTheRelaxationModulusThreeElement) {
  expect_step_relaxation(make_rectangle(kW, kH, 4, 4), sliding(), three_element(), kW * kT);
}

TEST(FeViscoelastic, PlaneStrainRelaxationScalesByThePlaneStrainFactor) {
  ModelOptions opt = sliding();
  opt.formulation = Formulation::kPlaneStrain;
  expect_step_relaxation(make_rectangle(kW, kH, 3, 5), opt,
                         ViscoelasticLaw::four_element(FourElementNetwork::kB, kTableII, kGamma),
                         kW * kT / (1.0 - kGamma * kGamma));
}

TEST(FeViscoelastic, TetrahedraRelaxAsTheRelaxationModulus) {
  ModelOptions opt = sliding();
  opt.formulation = Formulation::kSolid;
  const double D = 0.04;
  for (TetSplit split : {TetSplit::kFive, TetSplit::kSix}) {
    expect_step_relaxation(make_box(kW, D, kH, 2, 2, 2, split), opt, network_b(), kW * D);
  }
}

TEST(FeViscoelastic, ConstantRateRampAndHoldMatchesTheConvolutionIntegral) {
  // Seed 002's fast push: 0.5 mm/s to 9.6 mm (19.2 s), then held; 0.1 s steps. Simpson with
  // 20,000 intervals has error ~ h^4 E''''/180 ~ (1e-3 / 4.5)^4 E: far below the 1e-8 of the
  // peak asked (measured 1.8e-14).
  const double speed = 0.5e-3, depth = 9.6e-3, t_r = depth / speed;
  for (const ViscoelasticLaw& law : {network_b(), three_element()}) {
    ContinuumModel model(make_rectangle(kW, kH, 4, 4, TriangleSplit::kUniform), law, sliding());
    const auto rate = [&](double s) { return s <= t_r ? speed / kH : 0.0; };
    double peak = 0.0, worst = 0.0;
    std::vector<std::pair<double, double>> samples;
    for (int i = 1; i <= 600; ++i) {
      const double t = 0.1 * i;
      model.step(t - model.time_s(), std::min(t, t_r) * speed);
      if (i % 25 == 0) samples.emplace_back(t, model.plate_force_N());
      peak = std::max(peak, model.plate_force_N());
    }
    for (const auto& [t, F] : samples) {
      const double expected = kW * kT * convolution(law, rate, t_r, t, 20000);
      worst = std::max(worst, std::abs(F - expected) / peak);
    }
    EXPECT_LT(worst, 1e-8);
    ::testing::Test::RecordProperty("worst_relative_error", sci(worst));
  }
}

// Plate force at t = 20 s for the smooth history depth(t) = D (1 - cos(pi t / 20 s)) / 2 with
// step dt, on a bonded floor (non-homogeneous field).
double smooth_push_force(double dt) {
  ModelOptions opt;
  opt.thickness_m = kT;
  opt.floor = FloorCondition::kBonded;
  ContinuumModel model(make_rectangle(kW, kH, 4, 4), network_b(), opt);
  const double D = 5e-3, T = 20.0;
  const int n = static_cast<int>(std::lround(T / dt));
  for (int i = 1; i <= n; ++i) {
    const double t = i * dt;
    model.step(t - model.time_s(), D * 0.5 * (1.0 - std::cos(M_PI * t / T)));
  }
  return model.plate_force_N();
}

TEST(FeViscoelastic, HalvingTheTimeStepConvergesAtSecondOrder) {
  // The update is exact for a strain rate constant in each step, so for a smooth history the
  // only error is the secant rate: O(dt^2). Successive differences of dt = 2, 1, 0.5, 0.25 s
  // must fall by 4 (measured 3.9 to 4.0; asked 3.5 to 4.5).
  std::vector<double> F;
  for (double dt : {2.0, 1.0, 0.5, 0.25, 0.125}) F.push_back(smooth_push_force(dt));
  for (std::size_t i = 0; i + 2 < F.size(); ++i) {
    const double ratio = (F[i] - F[i + 1]) / (F[i + 1] - F[i + 2]);
    EXPECT_GT(ratio, 3.5) << i;
    EXPECT_LT(ratio, 4.5) << i;
    ::testing::Test::RecordProperty("ratio_" + std::to_string(i), sci(ratio));
  }
}

TEST(FeViscoelastic, FactorisesOncePerStepSizeAndContactSet) {
  ContinuumModel model(make_rectangle(kW, kH, 4, 4), network_b(), sliding());
  for (int i = 1; i <= 20; ++i) model.step(0.1, 0.05e-3 * i);
  // Step 1 factorises twice (free body, then with the plate's nodes); the rest reuse it.
  EXPECT_EQ(model.factorisations(), 2);
  model.step(0.2, 1.1e-3);
  EXPECT_EQ(model.factorisations(), 3);
}

}  // namespace
}  // namespace rheo::fe
