// Every benchmark model stays finite for ten times the steps one benchmark repetition runs
// (a repetition count the library may multiply; the restart keeps any run length safe).
#include <gtest/gtest.h>

#include <cmath>

#include "bench/bench_models.hpp"

namespace rheo::bench {
namespace {

constexpr int kRunLengthFactor = 10;

TEST(BenchModelsTest, EveryModelRunsTenTimesABenchmarksStepsWithoutNumericalFailure) {
  for (const BenchModel& m : bench_models()) {
    SCOPED_TRACE(m.scenario);
    ScenarioLoop loop(m.scenario);
    const long long steps = kRunLengthFactor * m.steps;
    double peak = 0.0;
    for (long long i = 0; i < steps; ++i) {
      const double force = loop.step();  // throws rheo::Error on non-finite state
      ASSERT_TRUE(std::isfinite(force)) << "step " << i;
      peak = std::max(peak, force);
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
