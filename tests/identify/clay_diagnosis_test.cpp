// End to end on the shipped virtual clay: the demo's finding and its held-out gain.
#include <gtest/gtest.h>

#include "host/identify/diagnose.hpp"

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
  EXPECT_EQ(j["candidates"].size(), 5u);
}

}  // namespace
}  // namespace rheo::identify
