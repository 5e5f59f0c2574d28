// The object model the fits run (host/identify/object_specimen.hpp): a load cell on its
// plate reads what a load cell reads at every switch of the protocol, and a diagnosis of data
// from the project's own simulation with no effect in it says `none`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "host/identify/diagnose.hpp"
#include "host/identify/object_specimen.hpp"
#include "host/identify/virtual_clay.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::identify {
namespace {

// Seed 002's specimen and the shipped virtual clay's material (data/README.md).
const Geometry kClay{80.0, 80.0, 12.5};

SpecimenParams clay() {
  SpecimenParams p;
  p.E1 = 83194;
  p.c1 = 44437.5;
  p.c2 = 4.43931e7;
  p.E2 = 40336;
  p.c3 = 184167;
  return p;
}

// Push 9.6 mm at 0.5 mm/s, hold 20 s, release at 0.5 mm/s, 10 s after; 10 Hz.
Measurement protocol() { return push_hold_release(kClay, 9.6, 0.5, 20.0, 0.5, 10.0, 10.0); }

// One clay, one simulation: the built-in clay_push scenario is the object model the fits
// run for its specimen on --mesh 2d:5x5 (mesh, stable-step masses, plate rule). Its own run,
// sampled every 10 ms, and the fits' simulation of that record with clay_push's material
// read the same plate force.
TEST(ObjectModel, ClayPushIsTheObjectModelTheFitsRun) {
  const Scenario s = load_scenario("clay_push");
  const Model model = s.build_model();
  Simulator sim(model, s.options);
  Measurement record;
  record.source = "clay_push";
  record.geometry = Geometry{s.block.sz * 1e3, s.block.sx * 1e3, s.block.sy * 1e3};
  const long long steps = s.default_steps();
  constexpr long long kEvery = 10;
  double peak = 0.0;
  for (long long i = 1; i <= steps; ++i) {
    const double f = sim.step(s.plate_z(model, i)).plate_force_N;
    peak = std::max(peak, f);
    if (i % kEvery != 0) continue;
    record.time_s.push_back(static_cast<double>(i) * s.options.dt);
    record.plate_mm.push_back(s.plate_mm(i));
    record.force_N.push_back(f);
    record.surface_mm.push_back(std::nan(""));
  }
  const EdgeMaterial& mat = s.block.material;
  SpecimenParams p;
  p.E1 = mat.k1;
  p.c1 = mat.c1;
  p.c2 = mat.c2;
  p.E2 = mat.k2;
  p.c3 = mat.c3;
  SimulationOptions o;
  o.mesh = parse_object_mesh("2d:5x5");
  const Prediction fits = simulate(record, p, o);
  double worst = 0.0;
  for (std::size_t k = 0; k < record.size(); ++k) {
    worst = std::max(worst, std::abs(fits.force_N[k] - record.force_N[k]));
  }
  ASSERT_GT(peak, 1.0);
  // The two differ by the rounding of the step (the fits take the sample interval / 10 from
  // the record's times) and of the plate's path between samples.
  EXPECT_LT(worst, 1e-9 * peak) << "largest difference " << worst << " N of a " << peak << " N peak";
}

TEST(ObjectModel, PlateForceHasNoDropOrOvershootAtAnySwitchOfTheProtocol) {
  const Measurement m = protocol();
  const Prediction fit = simulate(m, clay(), {});
  SimulationOptions fine;
  fine.steps_per_sample = 160;
  const Prediction truth = simulate(m, clay(), fine);
  double peak = 0.0;
  for (double f : truth.force_N) peak = std::max(peak, f);
  // A good load cell of this range: 0.2 % of the peak.
  const double rig_noise = 2e-3 * peak;
  const double t_push = 9.6 / 0.5, t_hold = t_push + 20.0;
  for (std::size_t i = 1; i < m.size(); ++i) {
    const double t = m.time_s[i];
    if (m.plate_mm[i] > 0.0 && t < t_hold + 1.0) {
      // The plate is down and the object pushes: never a sample at 0 N.
      EXPECT_GT(fit.force_N[i], 0.2 * truth.force_N[i]) << "t = " << t;
    }
    // Near each switch (start, push -> hold, hold -> release) the default steps give the
    // converged force within the rig's noise.
    for (double s : {0.0, t_push, t_hold}) {
      if (std::abs(t - s) <= 0.35) {
        EXPECT_NEAR(fit.force_N[i], truth.force_N[i], rig_noise) << "t = " << t;
      }
    }
    // During the hold the force relaxes: no overshoot after the stop.
    if (t > t_push && t <= t_hold && m.time_s[i - 1] >= t_push) {
      EXPECT_LE(fit.force_N[i], fit.force_N[i - 1] + 1e-9 * peak) << "t = " << t;
    }
  }
}

// A log-sampled two-exponential relaxation table (0.05 s to 16.6 s at 5 % steps), whose
// step plan grows the step (and the masses) 16-fold, with a Maxwell arm and a small Voigt
// damper: the parameters the fit of this table finds. With the arm's spring lagging one step
// behind the motion (explicit Euler for that spring) the force grew to 17 N once the step
// reached 32 ms; the arm acting on its updated extension (evaluate_edge arm_lead) keeps it
// stable and close to the table.
TEST(ObjectModel, AMaxwellArmStaysStableWhenTheStepGrowsOnALogSampledTable) {
  std::string table = "time_s\tG_Pa\n";
  for (int i = 0; i < 120; ++i) {
    const double t = 0.05 * std::pow(1.05, i);
    table += std::to_string(t) + "\t" +
             std::to_string(1000.0 * std::exp(-t / 0.5) + 2000.0 * std::exp(-t / 20.0)) + "\n";
  }
  ImportOptions io;
  io.geometry = Geometry{8.0, 30.0, 30.0};
  const Measurement m = parse_measurement_text(table, "two_exp.tsv", io);
  SpecimenParams p;
  p.E1 = 2724.63;
  p.c1 = 48.8974;
  p.c2 = 29569.4;
  p.E2 = 817.496;
  p.c3 = 891.903;
  const StepPlan plan = step_plan(m, p, {});
  ASSERT_GE(plan.dt.back() / plan.smallest, 8.0) << "the step should grow on this record";
  const Prediction pr = simulate(m, p, {});
  const double peak = *std::max_element(m.force_N.begin(), m.force_N.end());
  for (std::size_t i = 0; i < m.size(); ++i) {
    ASSERT_TRUE(std::isfinite(pr.force_N[i]));
    // These parameters are not the table's (their RMSE is 20 % of the peak); a blow-up is
    // orders of magnitude beyond that.
    EXPECT_LT(std::abs(pr.force_N[i] - m.force_N[i]), 0.5 * peak) << "sample " << i << " t "
                                                                    << m.time_s[i];
  }
}

TEST(ObjectModel, MeshTextRoundTripsAndBadMeshesAreRefusedWithTheExpectedForm) {
  EXPECT_EQ(parse_object_mesh("2d:auto").text(), "2d:auto");
  EXPECT_EQ(parse_object_mesh("2d:4x3").text(), "2d:4x3");
  EXPECT_EQ(parse_object_mesh("3d:3x2x3:truss").text(), "3d:3x2x3:truss");
  EXPECT_EQ(parse_object_mesh("2d:auto").resolved(kClay).text(), "2d:3x3");
  EXPECT_EQ(parse_object_mesh("2d:auto").resolved(Geometry{10.0, 40.0, 40.0}).text(), "2d:9x3");
  for (const char* bad : {"", "3d:auto", "2d:1x3", "2d:3x3x3", "4d:3x3", "2d:3x13", "2d:3xa"}) {
    try {
      parse_object_mesh(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("expected 2d:auto, 2d:NXxNZ or 3d:NXxNYxNZ"),
                std::string::npos)
          << e.what();
    }
  }
}

// Data from the project's own simulation (the reference simulator on a finer mesh than the
// fit's) with a plain three-element material and load-cell noise: nothing to find.
class OwnSimulationNull : public ::testing::TestWithParam<int> {};

TEST_P(OwnSimulationNull, DiagnosisSaysNone) {
  std::mt19937 rng(static_cast<std::uint32_t>(GetParam()));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SpecimenParams p;
  p.E1 = 3e4 * std::pow(10.0, u(rng));     // 30 to 300 kPa
  const double tau = 20.0 * std::pow(10.0, u(rng));  // 20 to 200 s
  const double eta = p.E1 * tau;
  p.c1 = (0.002 + 0.02 * u(rng)) * eta;
  p.c2 = eta - p.c1;
  const Geometry g{40.0 + 40.0 * u(rng), 60.0 + 40.0 * u(rng), 12.5};
  const double depth = 0.1 * g.height_mm;
  SimulationOptions truth;
  truth.mesh = parse_object_mesh("2d:7x5");
  truth.steps_per_sample = 40;
  auto make = [&](double speed, double hold, std::uint32_t seed) {
    Measurement m = push_hold_release(g, depth, speed, hold, 0.5, 10.0, 10.0);
    m.source = "own_simulation_" + std::to_string(seed);
    const Prediction pr = simulate(m, p, truth);
    m.force_N = pr.force_N;
    double peak = 0.0;
    for (double f : m.force_N) peak = std::max(peak, f);
    add_load_cell_noise(m, 3e-3 * peak, 0.0, seed);
    return m;
  };
  const std::vector<Measurement> fit{make(0.5, 20.0, 100 + GetParam())};
  const std::vector<Measurement> holdout{make(0.2, 40.0, 200 + GetParam())};
  const Diagnosis d = diagnose(fit, holdout);
  std::string judged;
  for (const CandidateFit& c : d.candidates) {
    judged += "\n  " + c.fit.spec.name() + ": " +
              (c.judgement.qualifies ? "qualifies" : c.judgement.reason);
  }
  EXPECT_EQ(d.cause, Extension::kNone) << d.evidence << judged;
}

INSTANTIATE_TEST_SUITE_P(Seeds, OwnSimulationNull, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace rheo::identify
