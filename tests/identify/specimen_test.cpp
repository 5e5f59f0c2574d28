#include "host/identify/specimen.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/identify/virtual_clay.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::identify {
namespace {

// These tests are about the 1-D column (the first guess); the object model has its own
// (object_model_test.cpp).
SimulationOptions column_options() {
  SimulationOptions o;
  o.form = SpecimenForm::kColumn;
  return o;
}
const SimulationOptions kColumn = column_options();

// Trapezoidal rule with at least 10 steps per time constant: local error ~ (dt/tau)^3/12.
constexpr double kRelaxationRelTol = 2e-3;
// A 10 ms strain ramp instead of an ideal step shifts the two-arm response by ~0.1 %.
constexpr double kTwoArmRelTol = 1e-2;

Measurement step_then_hold(double depth_mm, double ramp_s, std::vector<double> sample_times) {
  Measurement m;
  m.geometry = Geometry{10.0, 20.0, 20.0};
  for (double t : sample_times) {
    m.time_s.push_back(t);
    m.plate_mm.push_back(t < ramp_s ? depth_mm * t / ramp_s : depth_mm);
    m.force_N.push_back(0.0);
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  return m;
}

TEST(SpecimenModel, HeldStrainRelaxesWithTimeConstantC1PlusC2OverE1) {
  SpecimenParams p;
  p.E1 = 5e4;
  p.c1 = 5e4;
  p.c2 = 2e5;  // tau = 5 s
  const double tau = (p.c1 + p.c2) / p.E1;
  const Measurement m = step_then_hold(1.0, 0.5, {0.5, 1.0, 2.0, 4.0, 8.0, 12.0});
  const Prediction pr = simulate(m, p, kColumn);
  for (std::size_t i = 2; i < m.size(); ++i) {
    const double expected = pr.force_N[1] * std::exp(-(m.time_s[i] - m.time_s[1]) / tau);
    EXPECT_NEAR(pr.force_N[i], expected, kRelaxationRelTol * pr.force_N[1])
        << "t = " << m.time_s[i];
  }
}

TEST(SpecimenModel, ClayParametersRelaxWithTheTwoExponentialsOfSeed002ModelB) {
  const FourElementB b;
  const RelaxationArms arms = relaxation_arms(b);
  EXPECT_NEAR(arms.tau_fast, 4.566, 1e-2);
  EXPECT_NEAR(arms.tau_slow, 534.1, 1.0);
  EXPECT_NEAR(arms.g_fast + arms.g_slow, b.E2, 1e-6 * b.E2);
  const SpecimenParams p = clay_column_params(b, 1e-6);
  const double ramp = 0.01;
  Measurement m = step_then_hold(0.1, ramp, {0.01, 1.0, 3.0, 10.0, 30.0, 100.0});
  m.geometry = Geometry{12.5, 80.0, 80.0};
  const Prediction pr = simulate(m, p, kColumn);
  const double strain = 0.1 / 12.5;
  for (std::size_t i = 1; i < m.size(); ++i) {
    const double t = m.time_s[i] - ramp / 2;
    const double g =
        arms.g_slow * std::exp(-t / arms.tau_slow) + arms.g_fast * std::exp(-t / arms.tau_fast);
    const double expected = g * strain * m.geometry.area_m2();
    EXPECT_NEAR(pr.force_N[i], expected, kTwoArmRelTol * expected) << "t = " << m.time_s[i];
  }
}

TEST(SpecimenModel, ReleasedColumnLosesContactReadsZeroAndKeepsAResidualDeformation) {
  SpecimenParams p;
  p.E1 = 5e4;
  p.c1 = 5e4;
  p.c2 = 5e5;
  Measurement m;
  m.geometry = Geometry{10.0, 20.0, 20.0};
  for (int i = 0; i <= 300; ++i) {
    const double t = 0.1 * i;
    double plate = t < 4 ? 0.5 * t : (t < 14 ? 2.0 : std::max(0.0, 2.0 - 0.5 * (t - 14)));
    m.time_s.push_back(t);
    m.plate_mm.push_back(plate);
    m.force_N.push_back(0.0);
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  const Prediction pr = simulate(m, p, kColumn);
  EXPECT_TRUE(pr.contact[100]);
  EXPECT_GT(pr.force_N[100], 0.0);
  EXPECT_FALSE(pr.contact.back());
  EXPECT_EQ(pr.force_N.back(), 0.0);
  EXPECT_GT(pr.surface_mm.back(), 0.0);
  EXPECT_LT(pr.surface_mm.back(), 2.0);
}

TEST(SpecimenModel, NonPositiveViscosityIsRefusedWithItsName) {
  SpecimenParams p;
  p.E1 = 5e4;
  p.c1 = 0.0;
  p.c2 = 5e5;
  const Measurement m = step_then_hold(1.0, 0.5, {0.5, 1.0, 2.0});
  try {
    simulate(m, p, kColumn);
    FAIL() << "expected rheo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("c1"), std::string::npos);
  }
}

// The column model is the quasi-static (massless) limit of the reference Simulator on the
// same coarse Model. With a small mass (inertia time m/c ~ 1e-4 s against a 2 s push) the
// two must agree up to inertia and the Simulator's first-order time stepping.
constexpr double kReferenceAgreementRelTol = 1e-2;

TEST(SpecimenModel, AgreesWithTheReferenceSimulatorOnTheSameCoarseModel) {
  SpecimenParams p;
  p.E1 = 5e4;
  p.c1 = 5e4;
  p.c2 = 5e5;
  p.E2 = 3e4;
  p.c3 = 6e4;
  Measurement m;
  m.geometry = Geometry{10.0, 20.0, 20.0};
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.05 * i;
    m.time_s.push_back(t);
    m.plate_mm.push_back(t < 2 ? 0.5 * t : 1.0);
    m.force_N.push_back(0.0);
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  const Prediction pr = simulate(m, p, kColumn);

  Model model = coarse_model(m.geometry, p);
  model.mass = {1e-2, 1e-2};
  SimOptions options;
  options.dt = 0.5 * max_stable_dt(model, Integrator::kSemiImplicitEuler);
  Simulator sim(model, options);
  const double h = m.geometry.height_m();
  double peak = 0.0;
  for (double f : pr.force_N) peak = std::max(peak, f);
  std::size_t next = 1;
  double t = 0.0;
  while (next < m.size()) {
    t += options.dt;
    const double plate_mm = t < 2 ? 0.5 * t : 1.0;
    const StepReport r = sim.step(h - plate_mm * 1e-3);
    if (t >= m.time_s[next] - 0.5 * options.dt) {
      EXPECT_NEAR(r.plate_force_N, pr.force_N[next], kReferenceAgreementRelTol * peak)
          << "t = " << m.time_s[next];
      ++next;
    }
  }
}

}  // namespace
}  // namespace rheo::identify
