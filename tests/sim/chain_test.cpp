// Seed 000 ch. 2 (textbook chapter, Figures 2.5, 2.7, 2.10): four particles on a line,
// P0 fixed, joined by three identical elements; a force of 1 pulls P3 during [0, 20].
#include <gtest/gtest.h>

#include <cmath>

#include "sim/model.hpp"
#include "sim/simulator.hpp"

namespace rheo {
namespace {

constexpr double kDt = 1e-3;
constexpr double kLoadEnd = 20.0;

Model make_chain(const EdgeMaterial& material) {
  Model m;
  m.dim = 3;
  m.gravity = Vec3::Zero();
  m.floor = false;
  for (int i = 0; i < 4; ++i) {
    m.x0.push_back(Vec3(i, 0.0, 0.0));
    m.mass.push_back(1.0);
    m.flags.push_back(i == 0 ? kFixed : kFree);
  }
  for (int i = 0; i < 3; ++i) m.edges.push_back(Edge{i, i + 1, 1.0, 1.0, 0});
  m.materials.push_back(material);
  return m;
}

// Runs the chain until `until` with the load 1 on P3 while t < load_end.
Simulator run_chain(const EdgeMaterial& material, double until, double load_end = kLoadEnd) {
  SimOptions options;
  options.dt = kDt;
  Simulator sim(make_chain(material), options);
  std::vector<Vec3> load(4, Vec3::Zero());
  load[3] = Vec3(1.0, 0.0, 0.0);
  sim.set_external_force(load);
  const long long load_steps = std::llround(load_end / kDt);
  const long long steps = std::llround(until / kDt);
  for (long long k = 0; k < steps; ++k) {
    if (k == load_steps) sim.set_external_force({});
    sim.step(1e9);
  }
  return sim;
}

double displacement(const Simulator& sim, int i) { return sim.state().x[i].x() - i; }

// A series damper far stiffer than anything else makes the three-element edge a Voigt
// element; a_min = a_max = 1 keeps its Voigt length equal to its length.
EdgeMaterial voigt(double k, double b) {
  EdgeMaterial m;
  m.k1 = k;
  m.c1 = b;
  m.c2 = 1e9;
  m.a_min = 1.0;
  m.a_max = 1.0;
  return m;
}

TEST(VoigtChain, DisplacementsConvergeToForceOverEquivalentStiffness) {
  // Figure 2.5(b): m = 1, b = 2, k = 2. The slowest mode decays with about 5 s; after
  // 60 s of constant load its remainder is below 1e-5.
  constexpr double kSettledTolerance = 1e-4;
  const Simulator sim = run_chain(voigt(2.0, 2.0), 60.0, 60.0);
  EXPECT_NEAR(displacement(sim, 1), 0.5, kSettledTolerance);
  EXPECT_NEAR(displacement(sim, 2), 1.0, kSettledTolerance);
  EXPECT_NEAR(displacement(sim, 3), 1.5, kSettledTolerance);
}

TEST(VoigtChain, RecoversItsNaturalShapeAfterTheLoadIsRemoved) {
  constexpr double kRecoveredTolerance = 1e-4;
  const Simulator sim = run_chain(voigt(2.0, 2.0), 80.0, 20.0);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(displacement(sim, i), 0.0, kRecoveredTolerance);
}

TEST(MaxwellChain, ParticlesCreepAtForceOverEquivalentViscosity) {
  // Figure 2.7(a): m = 1, b = 40, k = 60; Maxwell = spring k1 in series with damper c2.
  EdgeMaterial m;
  m.k1 = 60.0;
  m.c1 = 0.0;
  m.c2 = 40.0;
  // The elastic oscillation of the masses is damped only through the dashpots; by
  // t = 20 the creep rates have settled to well within 2 %.
  constexpr double kRateTolerance = 0.02;
  const Simulator sim = run_chain(m, 20.0);
  EXPECT_NEAR(sim.state().v[1].x(), 0.025, 0.025 * kRateTolerance);
  EXPECT_NEAR(sim.state().v[2].x(), 0.050, 0.050 * kRateTolerance);
  EXPECT_NEAR(sim.state().v[3].x(), 0.075, 0.075 * kRateTolerance);
}

EdgeMaterial three_element() {
  // Figure 2.10(a): m = 1, b = 8 (Voigt damper), k = 2, b' = 40 (series damper).
  EdgeMaterial m;
  m.k1 = 2.0;
  m.c1 = 8.0;
  m.c2 = 40.0;
  return m;
}

TEST(ThreeElementChain, EachElementExtendsByAboutOneUnderTheLoad) {
  // Voigt part f/k = 0.5 (time constant b/k = 4 s, not quite settled at t = 20) plus the
  // creep f/b' * 20 = 0.5 of the series damper, less the start-up of the masses.
  constexpr double kTransientTolerance = 0.05;
  const Simulator sim = run_chain(three_element(), kLoadEnd);
  for (int i = 1; i < 4; ++i) {
    EXPECT_NEAR(displacement(sim, i) - displacement(sim, i - 1), 1.0, kTransientTolerance)
        << "element " << i - 1;
  }
}

TEST(ThreeElementChain, KeepsHalfOfTheExtensionAfterRelease) {
  // Momentum balance makes the impulse through every element equal to the load's (20),
  // so each series damper ends exactly 20 / 40 = 0.5 longer; the Voigt parts relax to 0.
  // Remaining error: the explicit step (dt = 1e-3) and the Voigt tail at t = 400.
  constexpr double kResidualTolerance = 2e-3;
  const Simulator sim = run_chain(three_element(), 400.0);
  for (int i = 1; i < 4; ++i) {
    EXPECT_NEAR(displacement(sim, i) - displacement(sim, i - 1), 0.5, kResidualTolerance)
        << "element " << i - 1;
  }
}

}  // namespace
}  // namespace rheo
