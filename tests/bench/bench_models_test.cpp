// Every benchmark model stays finite for ten times the steps one benchmark repetition runs
// (a repetition count the library may multiply; the restart keeps any run length safe).
//
// In CI the run is the fast CPU path on one thread, which FastPath/BuiltInScenario holds to
// the scalar reference within 1e-12 of the object size step by step; and a run that goes past
// the end of the protocol stops after its second period, once the period after the restart
// has repeated the first bit for bit (the restart puts the object back at rest, so every
// later period repeats it too). The whole run on the scalar reference is the `long` test in
// bench_models_long_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "bench/bench_models.hpp"

namespace rheo::bench {
namespace {

constexpr int kRunLengthFactor = 10;

TEST(BenchModelsTest, EveryModelRunsTenTimesABenchmarksStepsWithoutNumericalFailure) {
  for (const BenchModel& m : bench_models()) {
    SCOPED_TRACE(m.scenario);
    ScenarioLoop loop(m.scenario, CpuPath{true, 1});
    const long long wanted = kRunLengthFactor * m.steps;
    const long long period = loop.period_steps();
    const bool repeats = wanted > period;
    const long long steps = repeats ? std::min(wanted, 2 * period) : wanted;
    std::vector<double> first;
    double peak = 0.0;
    for (long long i = 0; i < steps; ++i) {
      const double force = loop.step();  // throws rheo::Error on non-finite state
      ASSERT_TRUE(std::isfinite(force)) << "step " << i;
      peak = std::max(peak, force);
      if (i < period) {
        if (repeats) first.push_back(force);
      } else {
        ASSERT_EQ(force, first[static_cast<std::size_t>(i - period)])
            << "step " << i << ": the period after the restart does not repeat the first";
      }
    }
    EXPECT_EQ(loop.steps_done(), steps);
    // The plate really pushes: the benchmark exercises contact, not a block at rest.
    EXPECT_GT(peak, 0.0);
  }
}

TEST(BenchModelsTest, LoopRestartsFromRestWhenTheProtocolEnds) {
  ScenarioLoop loop("block5");
  const double first = loop.step();
  for (long long i = 1; i < loop.period_steps(); ++i) loop.step();
  EXPECT_TRUE(loop.at_end());
  EXPECT_DOUBLE_EQ(loop.step(), first);  // same state, same plate position: same force
}

}  // namespace
}  // namespace rheo::bench
