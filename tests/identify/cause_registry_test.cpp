// Causes as plug-ins: a cause that exists only in this file, added through the registry,
// is fitted, judged and named by the diagnosis like the built-in ones, and is not named
// when it is not registered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "host/identify/cause.hpp"
#include "host/identify/diagnose.hpp"
#include "host/identify/virtual_clay.hpp"
#include "sim/error.hpp"

namespace rheo::identify {
namespace {

// A load cell whose zero creeps: reading = force + rate t. One linear parameter, on the
// observation side, applied to the simulated reading after the simulation.
class SensorDrift final : public Cause {
 public:
  SensorDrift()
      : Cause("sensor_drift", "a load-cell offset growing linearly in time (drift_N_per_s)",
              CauseSide::kObservation) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    const double max_rate = s.peak_force_N / s.duration_s;
    return {{"drift_N_per_s", -max_rate, max_rate, false}};
  }

  void observe(FittedValues v, const DataScales&, const Measurement& m,
               Prediction& pr) const override {
    for (std::size_t i = 0; i < pr.force_N.size(); ++i) pr.force_N[i] += v[0] * m.time_s[i];
  }

  std::vector<std::vector<double>> starts(FittedValues, const DataScales& s) const override {
    const double rate = 0.01 * s.peak_force_N / s.duration_s;
    return {{-rate}, {rate}};
  }

  std::string implausible(FittedValues v, const DataScales& s) const override {
    if (std::abs(v[0]) * s.duration_s <= 0.1 * s.peak_force_N) return "";
    return "a drift over the record above 10 % of the peak force: not a creeping zero";
  }

  std::string explain(const EvidenceContext& e) const override {
    const std::size_t n = e.m.size();
    double early = 0.0, late = 0.0;
    for (std::size_t i = 0; i < n / 3; ++i) early += e.baseline_residual[i];
    for (std::size_t i = n - n / 3; i < n; ++i) late += e.baseline_residual[i];
    std::ostringstream s;
    s << std::setprecision(3) << "The baseline residual grows with time: mean "
      << early / static_cast<double>(n / 3) << " N over the first third of the record and "
      << late / static_cast<double>(n / 3) << " N over the last; a load-cell zero drifting by "
      << FittedValues(e.extended.values)[0] << " N/s follows it.";
    return s.str();
  }
};

constexpr char kDrift[] = "sensor_drift";
constexpr double kTrueRate = 0.005;  // [N/s], 0.12 N over the 24 s record
constexpr double kNoise = 0.01;      // [N]

// The column form: the drift acts on the reading, the specimen model's form does not matter
// for what is tested here, and the column keeps the seven fits at about a second.
DiagnoseOptions column_diagnosis() {
  DiagnoseOptions o;
  o.fit.simulation.form = SpecimenForm::kColumn;
  return o;
}

// A known three-element material under push, hold and release, read by a drifting load cell.
std::vector<Measurement> drifting_record() {
  SpecimenParams truth;
  truth.E1 = 5e4;
  truth.c1 = 5e4;
  truth.c2 = 5e5;
  Measurement m = push_hold_release(Geometry{10.0, 20.0, 20.0}, 2.0, 0.5, 10.0, 0.5, 6.0, 20.0);
  m.source = "drift.csv";
  m.force_N = simulate(m, truth, column_diagnosis().fit.simulation).force_N;
  for (std::size_t i = 0; i < m.size(); ++i) m.force_N[i] += kTrueRate * m.time_s[i];
  add_load_cell_noise(m, kNoise, 0.0, 21);
  return {m};
}

bool names_a_candidate(const Diagnosis& d, const std::string& cause) {
  return std::any_of(d.candidates.begin(), d.candidates.end(),
                     [&](const CandidateFit& c) { return c.fit.spec.cause_name() == cause; });
}

// Registers for the scope of a test, so that a failing test leaves the registry as it was.
struct ScopedCause {
  explicit ScopedCause(CausePtr c) : name(c->name()) { register_cause(std::move(c)); }
  ~ScopedCause() { unregister_cause(name); }
  std::string name;
};

TEST(CauseRegistry, BuiltInCausesInTheirOrder) {
  std::vector<std::string> names;
  for (const CausePtr& c : registered_causes()) names.push_back(c->name());
  EXPECT_EQ(names, (std::vector<std::string>{"second_relaxation_time", "force_dependent_damping",
                                             "strain_hardening", "sensor_lag", "sensor_offset",
                                             "relaxation_spectrum"}));
  EXPECT_EQ(extension_names(),
            "second_relaxation_time, force_dependent_damping, strain_hardening, sensor_lag, "
            "sensor_offset, relaxation_spectrum");
  EXPECT_EQ(extension_from_name("three_element"), "none");
  EXPECT_EQ(model_spec("sensor_lag", DataScales{}).name(), "three_element+sensor_lag");
  EXPECT_THROW(extension_from_name(kDrift), Error);
}

TEST(CauseRegistry, RunTimeRegistrationIsListedFoundAndRemoved) {
  {
    const ScopedCause drift(std::make_shared<SensorDrift>());
    EXPECT_EQ(registered_causes().back()->name(), kDrift);
    EXPECT_NE(extension_names().find(", sensor_drift"), std::string::npos);
    const ModelSpec spec = model_spec(kDrift, DataScales{});
    EXPECT_EQ(spec.name(), "three_element+sensor_drift");
    ASSERT_EQ(spec.params.size(), kBaselineParams + 1);
    EXPECT_EQ(spec.params.back().name, "drift_N_per_s");
    EXPECT_FALSE(spec.params.back().log_scale);
    // A name is one cause: neither a second registration nor the baseline's names.
    EXPECT_THROW(register_cause(std::make_shared<SensorDrift>()), Error);
  }
  EXPECT_EQ(find_cause(kDrift), nullptr);
  EXPECT_EQ(registered_causes().size(), builtin_causes().size());
}

// Not registered: the diagnosis cannot name it (whatever it names instead).
TEST(CauseRegistry, ADiagnosisCannotNameACauseThatIsNotRegistered) {
  const Diagnosis without = diagnose(drifting_record(), {}, column_diagnosis());
  EXPECT_NE(without.cause, kDrift);
  EXPECT_FALSE(names_a_candidate(without, kDrift));
}

TEST(CauseRegistry, DiagnosisNamesACauseAddedThroughTheRegistryAlone) {
  const std::vector<Measurement> data = drifting_record();
  const DiagnoseOptions options = column_diagnosis();
  const ScopedCause drift(std::make_shared<SensorDrift>());
  const Diagnosis d = diagnose(data, {}, options);
  ASSERT_EQ(d.cause, kDrift) << d.evidence;
  EXPECT_EQ(d.candidates.size(), builtin_causes().size() + 1);
  EXPECT_EQ(diagnosis_json(d)["finding"]["cause"], kDrift);
  EXPECT_NE(d.evidence.find("drifting by"), std::string::npos) << d.evidence;
  // Its fitted rate has an interval, and the interval holds the rate the data were made with.
  const ParamEstimate& rate = d.extended().estimates.at(kBaselineParams);
  EXPECT_EQ(rate.name, "drift_N_per_s");
  EXPECT_TRUE(rate.unidentifiable.empty()) << rate.unidentifiable;
  ASSERT_TRUE(rate.ci_low && rate.ci_high);
  EXPECT_LT(*rate.ci_low, kTrueRate);
  EXPECT_GT(*rate.ci_high, kTrueRate);
  // ... and is narrow enough to mean something: a fifth of the rate at most.
  EXPECT_LT(*rate.ci_high - *rate.ci_low, 0.2 * kTrueRate);
  // The drift is fitted to the noise.
  EXPECT_LT(d.extended().rmse_force_N, 1.2 * kNoise);
}

}  // namespace
}  // namespace rheo::identify
