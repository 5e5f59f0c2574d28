// End to end on the shipped virtual clay: the demo's finding and its held-out gain.
#include <gtest/gtest.h>

#include <algorithm>

#include "host/identify/diagnose.hpp"
#include "tests/test_paths.hpp"

namespace rheo::identify {
namespace {

const std::string kData = std::string(RHEO_SOURCE_DIR) + "/data/";

TEST(VirtualClay, DiagnosisNamesSecondRelaxationTimeAndGainsOnTheSlowTest) {
  const std::vector<Measurement> fit{read_measurement_csv(kData + "clay_fast.csv")};
  const std::vector<Measurement> holdout{read_measurement_csv(kData + "clay_slow.csv")};
  const Diagnosis d = diagnose(fit, holdout);
  EXPECT_EQ(d.cause, Extension::kSecondRelaxationTime) << d.evidence;
  ASSERT_TRUE(d.baseline_rmse_holdout_N && d.extended_holdout());
  EXPECT_GT(*d.baseline_rmse_holdout_N / *d.extended_holdout(), 1.0);
  const auto j = diagnosis_json(d);
  EXPECT_EQ(j["finding"]["cause"], "second_relaxation_time");
  for (const char* key : {"baseline", "finding", "extended", "gain", "candidates"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["candidates"].size(), registered_causes().size());
  // The generator's relaxation times (data/README.md): 534.1 s and 4.566 s, recovered by
  // the object model of the fit (a coarser mesh than the generator's) within 10 %.
  const auto& v = d.extended().values;
  const double tau_a = (v[1] + v[2]) / v[0], tau_b = v[4] / v[3];
  EXPECT_NEAR(std::max(tau_a, tau_b), 534.1, 53.4);
  EXPECT_NEAR(std::min(tau_a, tau_b), 4.566, 0.4566);
  // It fits to the noise drawn (0.02 N).
  EXPECT_LT(d.extended().rmse_force_N, 1.5 * 0.02);
}

}  // namespace
}  // namespace rheo::identify
