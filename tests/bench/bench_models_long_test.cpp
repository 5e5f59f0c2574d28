// The whole of BenchModelsTest's run (bench_models_test.cpp) on the scalar reference model:
// every benchmark model stays finite for ten times the steps one benchmark repetition runs,
// restarts included. Label `long` (about 35 s on two busy cores).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bench/bench_models.hpp"

namespace rheo::bench {
namespace {

constexpr int kRunLengthFactor = 10;

TEST(BenchModelsLong, EveryModelRunsTenTimesABenchmarksStepsOnTheScalarReference) {
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
    EXPECT_GT(peak, 0.0);
  }
}

}  // namespace
}  // namespace rheo::bench
