// The fast CPU path (sim/fast/) against the scalar reference model: same answers within
// 1e-12 of the object size, on every built-in scenario over 10,000 steps and on models with
// every feature it computes; refusals for what it does not; failures named as the scalar
// path names them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <span>
#include <string>

#include "sim/error.hpp"
#include "sim/fast/fast_simulator.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"
#include "tests/test_paths.hpp"

namespace rheo::fast {
namespace {

constexpr double kTolerance = 1e-12;  // of the object size

struct Gap {
  double position = 0.0;  // largest |x_fast - x_scalar| / size over the checks
  double force = 0.0;     // largest plate-force difference / peak force
  double peak = 0.0;      // largest plate force [N]
};

// Runs both paths `steps` steps of the scenario's protocol, comparing the positions every
// `every` steps and the plate force every step.
Gap compare(const Scenario& sc, const Model& model, long long steps, int threads,
            long long every = 500) {
  Simulator scalar(model, sc.options);
  FastSimulator fast(model, sc.options, threads);
  Gap gap;
  double force_gap = 0.0;
  for (long long s = 1; s <= steps; ++s) {
    const double z = sc.plate_z(model, s);
    const StepReport a = scalar.step(z);
    const StepReport b = fast.step(z);
    EXPECT_EQ(a.contacts, b.contacts) << "step " << s;
    force_gap = std::max(force_gap, std::abs(a.plate_force_N - b.plate_force_N));
    gap.peak = std::max(gap.peak, std::abs(a.plate_force_N));
    if (s % every == 0 || s == steps) {
      const State f = fast.state();
      for (int i = 0; i < model.num_particles(); ++i) {
        gap.position = std::max(gap.position, (f.x[i] - scalar.state().x[i]).norm() / model.size);
      }
      for (int k = 0; k < model.num_edges(); ++k) {
        EXPECT_NEAR(f.d[k], scalar.state().d[k], kTolerance * model.size) << "edge " << k;
      }
    }
  }
  gap.force = gap.peak > 0.0 ? force_gap / gap.peak : force_gap;
  std::printf("%lld steps, %d threads: positions within %.3g of the size, plate force within %.3g "
              "of its peak %.4g N\n", steps, fast.threads(), gap.position, gap.force, gap.peak);
  return gap;
}

class BuiltInScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltInScenario, TenThousandStepsStayWithin1e12OfTheObjectSize) {
  const Scenario sc = load_scenario(GetParam());
  const Model model = sc.build_model();
  // Two threads: the split and the sums in thread order are what the default runs.
  const Gap gap = compare(sc, model, 10000, 2);
  RecordProperty("position_gap", std::to_string(gap.position));
  EXPECT_LE(gap.position, kTolerance);
  EXPECT_LE(gap.force, 1e-9);
  EXPECT_GT(gap.peak, 0.0);  // the plate pushed: contact is part of the comparison
}

// The built-in scenarios the fast path computes (the contact scenes run on the scalar path).
std::vector<std::string> fast_path_scenarios() {
  std::vector<std::string> names;
  for (const std::string& name : builtin_scenarios()) {
    const Scenario sc = load_scenario(name);
    if (fast::fast_path_refusal(sc.build_model(), sc.options).empty()) names.push_back(name);
  }
  return names;
}

INSTANTIATE_TEST_SUITE_P(FastPath, BuiltInScenario, ::testing::ValuesIn(fast_path_scenarios()),
                         [](const auto& info) { return info.param; });

TEST(FastPath, RefusesContactAndToolsNamingThem) {
  const Scenario tools = load_scenario("press_sphere");
  EXPECT_EQ(fast::fast_path_refusal(tools.build_model(), tools.options), "tools");
  const Scenario contact = load_scenario("six_objects");
  EXPECT_EQ(fast::fast_path_refusal(contact.build_model(), contact.options),
            "contact among objects");
  EXPECT_THROW(fast::FastSimulator(tools.build_model(), tools.options, 1), Error);
}

// A block5 variant for the feature tests: the scenario file's features, a model edit, and
// 3,000 steps (push and part of the hold).
Gap compare_variant(const std::string& file, void (*edit)(Scenario&, Model&), int threads = 1) {
  Scenario sc = load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/" + file);
  Model model = sc.build_model();
  if (edit) edit(sc, model);
  return compare(sc, model, 3000, threads);
}

TEST(FastPath, EveryEdgeFeatureAndVolumePreservationMatch) {
  // Nonlinear damper, hardening, an eight-arm spectrum, volume preservation.
  for (int threads : {1, 2}) {
    const Gap gap = compare_variant("block5_every_feature.json", nullptr, threads);
    EXPECT_LE(gap.position, kTolerance) << threads << " threads";
  }
}

TEST(FastPath, MaxwellArmAndHoldWhilePushingMatch) {
  const Gap gap = compare_variant("block5_every_edge_effect.json", [](Scenario&, Model& m) {
    for (EdgeMaterial& mat : m.materials) {
      mat.k2 = 0.3 * mat.k1;
      mat.c3 = 0.5 * mat.c2;
    }
    m.plate_contact = PlateContact::kHoldWhilePushing;
  });
  EXPECT_LE(gap.position, kTolerance);
}

TEST(FastPath, TwoDimensionalTrussWithAreaForcesMatches) {
  const Gap gap = compare_variant("block5_every_feature.json", [](Scenario& sc, Model& m) {
    BlockSpec spec = sc.block;
    spec.dim = 2;
    spec.structure = Structure::kTruss;
    m = make_block(spec);
    m.gravity = Vec3::Zero();  // the slender 2-D truss would sag below the plate's reach
    sc.options.dt = std::min(sc.options.dt, 0.5 * max_stable_dt(m, sc.options.integrator));
  });
  EXPECT_LE(gap.position, kTolerance);
}

TEST(FastPath, IrregularEdgesRunAsAnEdgeListWithSeveralMaterials) {
  // Half the edges get a second, stiffer material and the particle numbering is shuffled,
  // so the index offsets no longer repeat: the general edge list with gathers.
  const Gap gap = compare_variant("block5_every_edge_effect.json", [](Scenario&, Model& m) {
    const int n = m.num_particles();
    std::vector<int> to(n);
    std::iota(to.begin(), to.end(), 0);
    std::shuffle(to.begin(), to.end(), std::mt19937(7));
    Model shuffled = m;
    for (int i = 0; i < n; ++i) {
      shuffled.x0[to[i]] = m.x0[i];
      shuffled.mass[to[i]] = m.mass[i];
      shuffled.flags[to[i]] = m.flags[i];
    }
    EdgeMaterial stiff = m.materials[0];
    stiff.k1 *= 1.5;
    shuffled.materials.push_back(stiff);
    for (std::size_t k = 0; k < m.edges.size(); ++k) {
      shuffled.edges[k].s = to[m.edges[k].s];
      shuffled.edges[k].e = to[m.edges[k].e];
      shuffled.edges[k].material = static_cast<int>(k % 2);
    }
    for (auto& tet : shuffled.tetrahedra) {
      for (int& v : tet) v = to[v];
    }
    m = shuffled;
  });
  EXPECT_LE(gap.position, kTolerance);
}

// run() hands the threads all its steps in one job (neighbouring slabs wait for each other's
// flags, not for a join): the numbers are those of stepping one by one, bit for bit.
TEST(FastPath, ManyStepsInOneRunEqualSteppingOneByOneBitForBit) {
  const Scenario sc = load_scenario(std::string(RHEO_SOURCE_DIR) +
                                    "/data/scenarios/block5_every_feature.json");
  const Model model = sc.build_model();
  for (int threads : {2, 3}) {
    FastSimulator batched(model, sc.options, threads), single(model, sc.options, threads);
    std::vector<double> z;
    for (int s = 1; s <= 700; ++s) z.push_back(sc.plate_z(model, s));
    std::vector<StepReport> reports;
    for (std::size_t at = 0; at < z.size(); at += 350) {
      const std::vector<StepReport> part =
          batched.run(std::span<const double>(z).subspan(at, 350));
      reports.insert(reports.end(), part.begin(), part.end());
    }
    for (std::size_t s = 0; s < z.size(); ++s) {
      const StepReport r = single.step(z[s]);
      ASSERT_EQ(r.plate_force_N, reports[s].plate_force_N) << threads << " threads, step " << s;
      ASSERT_EQ(r.contacts, reports[s].contacts);
    }
    EXPECT_GT(reports.back().contacts, 0);
    EXPECT_EQ(batched.state().x, single.state().x);
    EXPECT_EQ(batched.state().d, single.state().d);
    EXPECT_EQ(batched.steps(), single.steps());
  }
}

TEST(FastPath, ALatticeUsesImplicitTopology) {
  const Scenario sc = load_scenario("block15");
  const FastSimulator fast(sc.build_model(), sc.options, 1);
  EXPECT_EQ(fast.layout().implicit_edges, fast.model().num_edges());
  EXPECT_NE(fast.describe().find("implicit lattice topology: 13 index offsets"), std::string::npos)
      << fast.describe();
}

TEST(FastPath, RefusesWhatItDoesNotComputeByName) {
  const Scenario sc = load_scenario("block5");
  Model model = sc.build_model();
  SimOptions rk4 = sc.options;
  rk4.integrator = Integrator::kRK4;
  EXPECT_EQ(fast_path_refusal(model, rk4), "the RK4 integrator");
  model.topology.enabled = true;
  model.topology.k = 100.0;
  EXPECT_EQ(fast_path_refusal(model, sc.options), "topology maintenance");
  try {
    FastSimulator f(model, sc.options);
    FAIL() << "accepted topology maintenance";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("topology maintenance"), std::string::npos) << e.what();
  }
}

TEST(FastPath, ANonFiniteStateIsNamedAsTheScalarPathNamesIt) {
  const Scenario sc = load_scenario("block5");
  const Model model = sc.build_model();
  Simulator scalar(model, sc.options);
  FastSimulator fast(model, sc.options, 2);
  State bad = scalar.state();
  bad.d[17] = std::nan("");
  scalar.mutable_state() = bad;
  fast.set_state(bad);
  std::string scalar_error, fast_error;
  try {
    scalar.step(sc.plate_z(model, 1));
  } catch (const Error& e) {
    scalar_error = e.what();
  }
  try {
    fast.step(sc.plate_z(model, 1));
  } catch (const Error& e) {
    fast_error = e.what();
  }
  EXPECT_FALSE(fast_error.empty());
  EXPECT_EQ(fast_error, scalar_error);
}

// A failure in the middle of a run() stops every thread at that step and names it; the
// simulator runs again from a state put back.
TEST(FastPath, AFailureInsideARunStopsAtItsStepAndTheSimulatorRunsOnAfterwards) {
  const Scenario sc = load_scenario("block5");
  const Model model = sc.build_model();
  FastSimulator fast(model, sc.options, 2);
  std::vector<double> z(50, sc.plate_z(model, 1));
  State bad = initial_state(model);
  bad.v[70].z() = std::numeric_limits<double>::infinity();
  fast.set_state(bad);
  try {
    fast.run(z);
    FAIL() << "ran through an infinite velocity";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("numerical failure at step 1 "), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(fast.steps(), 1);
  fast.set_state(initial_state(model));
  EXPECT_EQ(fast.run(z).size(), z.size());
  EXPECT_EQ(fast.steps(), 51);
}

TEST(FastPath, StateRoundTripsThroughTheSlotLayout) {
  const Scenario sc = load_scenario(std::string(RHEO_SOURCE_DIR) +
                                    "/data/scenarios/block5_every_feature.json");
  const Model model = sc.build_model();
  FastSimulator fast(model, sc.options, 2);
  State s = initial_state(model);
  for (std::size_t k = 0; k < s.d.size(); ++k) s.d[k] += 1e-6 * static_cast<double>(k % 7);
  for (std::size_t a = 0; a < s.spectrum.size(); ++a) s.spectrum[a] = 1e-7 * static_cast<double>(a % 11);
  s.t = 1.25;
  fast.set_state(s);
  const State back = fast.state();
  EXPECT_EQ(back.d, s.d);
  EXPECT_EQ(back.spectrum, s.spectrum);
  EXPECT_EQ(back.t, s.t);
}

}  // namespace
}  // namespace rheo::fast
