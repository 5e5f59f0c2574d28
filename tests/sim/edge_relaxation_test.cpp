// A single three-element edge held at a fixed length relaxes with one exponential of
// time constant (c1 + c2) / k1 (docs/model.md; the property seed 002 finds too simple).
#include <gtest/gtest.h>

#include <cmath>

#include "sim/model.hpp"
#include "sim/simulator.hpp"

namespace rheo {
namespace {

Model held_edge(const EdgeMaterial& material, double held_length) {
  Model m;
  m.gravity = Vec3::Zero();
  m.floor = false;
  m.x0 = {Vec3(0.0, 0.0, 0.0), Vec3(held_length, 0.0, 0.0)};
  m.mass = {1.0, 1.0};
  m.flags = {kFixed, kFixed};
  m.edges = {Edge{0, 1, 1.0, 1.0, 0}};
  m.materials = {material};
  return m;
}

double tension(const Simulator& sim) {
  std::vector<Vec3> f;
  std::vector<double> ddot, mdot;
  sim.internal_forces(sim.state(), f, ddot, mdot);
  return f[0].x();  // force on s = +T u, u = +x
}

TEST(HeldEdge, TensionRelaxesWithTimeConstantC1PlusC2OverK1) {
  EdgeMaterial mat;
  mat.k1 = 100.0;
  mat.c1 = 30.0;
  mat.c2 = 70.0;
  const double tau = (mat.c1 + mat.c2) / mat.k1;  // 1 s
  SimOptions options;
  options.dt = tau / 2000.0;
  Simulator sim(held_edge(mat, 1.2), options);
  // Just after a step stretch of 0.2 the Voigt part carries c2/(c1+c2) of it.
  sim.mutable_state().d[0] = 1.0 + 0.2 * mat.c2 / (mat.c1 + mat.c2);
  const double t0_tension = tension(sim);
  // At rest length held (ldot = 0): T = k1 (d - L) c2 / (c1 + c2).
  constexpr double kRoundoff = 1e-9;
  EXPECT_NEAR(t0_tension, mat.k1 * (sim.state().d[0] - 1.0) * mat.c2 / (mat.c1 + mat.c2),
              kRoundoff);
  const int steps = 4000;  // two time constants
  for (int k = 0; k < steps; ++k) sim.step(1e9);
  const double measured_tau = sim.state().t / std::log(t0_tension / tension(sim));
  // Explicit Euler on d shifts the rate by O(dt / tau) = 5e-4.
  constexpr double kTimeConstantTolerance = 1e-3;
  EXPECT_NEAR(measured_tau / tau, 1.0, kTimeConstantTolerance);
}

TEST(HeldEdge, MaxwellArmAddsASecondRelaxationTime) {
  EdgeMaterial mat;
  mat.k1 = 100.0;
  mat.c1 = 30.0;
  mat.c2 = 70.0;
  mat.k2 = 50.0;
  mat.c3 = 500.0;  // tau2 = 10 s, much slower than tau1 = 1 s
  SimOptions options;
  options.dt = 5e-4;
  Simulator sim(held_edge(mat, 1.2), options);
  sim.mutable_state().m[0] = 0.2;  // arm stretched by the step, Voigt part at rest
  const double t0 = tension(sim);
  EXPECT_NEAR(t0, mat.k2 * 0.2, 1e-12);           // exact: T = k2 m
  for (int k = 0; k < 20000; ++k) sim.step(1e9);  // 10 s
  // The arm relaxes alone: T = k2 m0 exp(-t k2/c3); explicit-Euler error O(dt k2/c3).
  constexpr double kArmRelaxationTolerance = 1e-3;
  EXPECT_NEAR(tension(sim) / t0, std::exp(-1.0), kArmRelaxationTolerance);
}

}  // namespace
}  // namespace rheo
