// End to end: a virtual experiment on a 2-D continuum (finite-element) block with one hidden
// effect or none (tests/identify/continuum_body.hpp: its own discretisation, material law,
// contact and time integration, no rheo code) goes through `rheo diagnose` as a subprocess,
// which fits the project's particle model and must name the effect without being told.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "tests/identify/continuum_body.hpp"
#include "tests/identify/diagnose_subprocess.hpp"
#include "tests/identify/hidden_effect_rate.hpp"

namespace rheo::testing {
namespace {

// Load-cell noise: 0.01 N rms on forces of a few newtons.
constexpr double kNoiseN = 0.01;

struct Case {
  std::string cause;  // the cause diagnose must name ("none" for the nulls)
  std::uint32_t seed;
};

// Specimen and base material drawn by seed (jitter 0.8-1.25), one effect switched on.
ContinuumBody body_for(const Case& c) {
  std::mt19937 rng(c.seed * 104729u + 3u);
  std::uniform_real_distribution<double> jitter(0.8, 1.25);
  ContinuumBody b;
  b.height_mm = 10.0 * jitter(rng);
  b.width_mm = 20.0 * jitter(rng);
  b.depth_mm = 20.0 * jitter(rng);
  ContinuumMaterial& m = b.m;
  m.E1 = 5e4 * jitter(rng);
  m.eta1 = 5e4 * jitter(rng);
  m.eta2 = 5e5 * jitter(rng);
  m.nu = 0.3 * jitter(rng);
  if (c.cause == "second_relaxation_time") {
    m.E_arm = 0.6 * m.E1 * jitter(rng);
    m.eta_arm = m.E_arm * 1.0 * jitter(rng);  // relaxation time about 1 s
  } else if (c.cause == "relaxation_spectrum") {
    m.spectrum_G = 0.5 * m.E1 * jitter(rng);
    m.spectrum_alpha = 0.35 * jitter(rng);
    m.spectrum_tau_lo = 0.05;
    m.spectrum_tau_hi = 500.0;
  } else if (c.cause == "strain_hardening") {
    m.hardening = 4.0 * jitter(rng);
  } else if (c.cause == "force_dependent_damping") {
    m.damping_stress = 5e3 * jitter(rng);
    m.damping_ratio = 10.0 * jitter(rng);
  } else if (c.cause == "sensor_lag") {
    m.lag_s = 0.4 * jitter(rng);
  } else if (c.cause == "sensor_offset") {
    m.offset_N = 0.06 * jitter(rng);
  }
  return b;
}

class ContinuumHiddenEffectTest : public ::testing::TestWithParam<Case> {};

TEST_P(ContinuumHiddenEffectTest, DiagnoseNamesTheHiddenCause) {
  const Case c = GetParam();
  const ContinuumBody body = body_for(c);
  // 1 mm of a ~10 mm block: small strain, where a linear finite-element body is valid (the
  // particle model is geometrically exact; at 20 % strain the two would differ by geometry).
  const PlateProtocol fit_protocol{1.0, 0.25, 10.0, 0.25, 6.0, kHiddenEffectRateHz};
  const PlateProtocol holdout_protocol{1.0, 0.1, 15.0, 0.5, 6.0, kHiddenEffectRateHz};
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("continuum_" + c.cause + "_" + std::to_string(c.seed));
  std::filesystem::create_directories(dir);
  const std::string note = "continuum hidden-effect test data (" + c.cause + ")";
  write_measurement_csv((dir / "fit.csv").string(), body,
                        run_continuum(body, fit_protocol, kNoiseN, c.seed), false, note);
  write_measurement_csv((dir / "holdout.csv").string(), body,
                        run_continuum(body, holdout_protocol, kNoiseN, c.seed + 1000), false,
                        note);
  const nlohmann::json j = run_diagnose(dir);
  ASSERT_FALSE(HasFailure());
  EXPECT_EQ(j["finding"]["cause"].get<std::string>(), c.cause)
      << j["finding"]["evidence"].get<std::string>() << "\n"
      << j["candidates"].dump();
  if (c.cause == "none") {
    EXPECT_DOUBLE_EQ(j["gain"]["holdout_rmse_ratio"].get<double>(), 1.0);
  } else {
    EXPECT_GT(j["gain"]["holdout_rmse_ratio"].get<double>(), 1.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    RHEO_HIDDEN_EFFECT_SUITE, ContinuumHiddenEffectTest,
    ::testing::Values(Case{"none", 11}, Case{"none", 12}, Case{"second_relaxation_time", 13},
                      Case{"relaxation_spectrum", 14}, Case{"strain_hardening", 15},
                      Case{"force_dependent_damping", 16}, Case{"sensor_lag", 17},
                      Case{"sensor_offset", 18}),
    [](const ::testing::TestParamInfo<Case>& info) {
      return info.param.cause + "_seed" + std::to_string(info.param.seed);
    });

}  // namespace
}  // namespace rheo::testing
