// Scenario loading: every built-in builds a valid, stable model; every kind of bad input
// is rejected with a message that names the file, the field and what was expected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/scenarios/builtin.hpp"
#include "sim/simulator.hpp"
#include "sim/stable_masses.hpp"
#include "tests/test_paths.hpp"

namespace rheo {
namespace {

using nlohmann::json;

// A scenario file in the test's temporary directory, removed afterwards.
class ScenarioFile {
 public:
  explicit ScenarioFile(const std::string& text) {
    path_ = (std::filesystem::temp_directory_path() /
             // ctest runs each test in its own process, in parallel: the pid keeps
             // their files apart.
             ("rheo_scenario_test_" + std::to_string(::getpid()) + "_" +
              std::to_string(counter_++) + ".json"))
                .string();
    std::ofstream(path_) << text;
  }
  ~ScenarioFile() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
};

json block5_json() { return json::parse(*find_builtin_scenario_text("block5")); }

// The message of the rheo::Error that loading `text` throws ("" if none).
std::string load_text_error(const std::string& text, std::string* file = nullptr) {
  ScenarioFile f(text);
  if (file) *file = f.path();
  try {
    load_scenario(f.path());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string load_error(const json& j, std::string* file = nullptr) {
  return load_text_error(j.dump(2), file);
}

TEST(BuiltinScenarios, AreThePapersModelsAndTheSeedContactScenes) {
  EXPECT_EQ(builtin_scenarios(),
            (std::vector<std::string>{"clay_push", "block5", "block15", "press_sphere", "slide_mu0",
                                      "slide_mu03", "six_objects", "roller_dough",
                                      "indent_sphere"}));
}

TEST(BuiltinScenarios, EachBuildsAValidModelWithAStableTimeStep) {
  for (const std::string& name : builtin_scenarios()) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(name);
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.description.empty());
    const Model model = s.build_model();
    EXPECT_GT(model.num_particles(), 0);
    EXPECT_GT(model.num_edges(), 0);
    EXPECT_LT(s.options.dt, max_stable_dt(model, s.options.integrator));
    EXPECT_GT(s.default_steps(), 1000);
    EXPECT_NO_THROW(Simulator(model, s.options));
  }
}

TEST(BuiltinScenarios, HaveThePaperParticleCounts) {
  EXPECT_EQ(load_scenario("block5").build_model().num_particles(), 5 * 5 * 5);
  EXPECT_EQ(load_scenario("block15").build_model().num_particles(), 15 * 15 * 16);
}

TEST(BuiltinScenarios, ClayPushFollowsSeed002Protocol) {
  // Seed 002: 80 x 80 x 12.5 mm, pushed 9.6 mm at 0.5 mm/s, held 47.88 s, released.
  constexpr double kTimeTolerance = 1e-9;  // exact arithmetic on the protocol knots
  const Scenario s = load_scenario("clay_push");
  EXPECT_DOUBLE_EQ(s.block.sz, 0.08);
  EXPECT_DOUBLE_EQ(s.block.sx, 0.08);
  EXPECT_DOUBLE_EQ(s.block.sy, 0.0125);
  EXPECT_DOUBLE_EQ(s.protocol.displacement_mm(9.6 / 0.5), 9.6);
  EXPECT_DOUBLE_EQ(s.protocol.displacement_mm(9.6 / 0.5 + 47.88), 9.6);
  EXPECT_NEAR(s.protocol.displacement_mm(2 * 9.6 / 0.5 + 47.88), 0.0, kTimeTolerance);
}

TEST(BuiltinScenarios, KeepTheWeightPhysicalUnderMassScaling) {
  // The 3-D clay lattice with its masses scaled by 5000 (clay_push before it took the fits'
  // stable-step masses).
  const Scenario s =
      load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/clay_push_lattice3d.json");
  ASSERT_GT(s.block.mass_scale, 1.0);
  const Model model = s.build_model();
  double weight = 0.0;
  for (double m : model.mass) weight += m * -model.gravity.z();
  const double real_weight = s.block.density * s.block.sx * s.block.sy * s.block.sz * 9.81;
  EXPECT_NEAR(weight, real_weight, 1e-9 * real_weight);
}

TEST(ScenarioFiles, LoadLikeTheBuiltinTheyWereCopiedFrom) {
  ScenarioFile f(*find_builtin_scenario_text("block5"));
  const Scenario s = load_scenario(f.path());
  EXPECT_EQ(s.build_model().num_edges(), load_scenario("block5").build_model().num_edges());
}

TEST(ScenarioFiles, UnknownNameOrMissingFileIsAnErrorListingTheBuiltins) {
  try {
    load_scenario("/nonexistent/dir/nothing.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("clay_push"), std::string::npos) << e.what();
  }
}

TEST(BadScenario, MalformedJsonNamesFileLineAndColumn) {
  std::string file;
  const std::string error = load_text_error("{\n  \"name\": \"x\",\n  \"mesh\": {,\n}\n", &file);
  EXPECT_NE(error.find(file + ":3:"), std::string::npos) << error;
  EXPECT_NE(error.find("malformed JSON"), std::string::npos) << error;
}

TEST(BadScenario, NanLiteralIsMalformedJsonWithItsPosition) {
  std::string text = block5_json().dump(2);
  text.replace(text.find("\"c1\": 2000.0"), 12, "\"c1\": NaN");
  const std::string error = load_text_error(text);
  EXPECT_NE(error.find("malformed JSON"), std::string::npos) << error;
}

TEST(BadScenario, NumberBeyondDoubleRangeIsNotFinite) {
  std::string text = block5_json().dump(2);
  text.replace(text.find("\"k1\": 20000.0"), 14, "\"k1\": 1e999");
  const std::string error = load_text_error(text);
  EXPECT_NE(error.find("not representable as a double"), std::string::npos) << error;
  // "k1" is the 3rd line of the material object: the position points into the file.
  EXPECT_NE(error.find(".json:"), std::string::npos) << error;
}

TEST(BadScenario, UnknownKeyIsRejectedWithItsPointer) {
  json j = block5_json();
  j["material"]["c_1"] = 3.0;
  std::string file;
  const std::string error = load_error(j, &file);
  EXPECT_NE(error.find(file + ": /material/c_1: unknown key"), std::string::npos) << error;
}

TEST(BadScenario, MissingFieldIsNamed) {
  json j = block5_json();
  j["material"].erase("k1");
  EXPECT_NE(load_error(j).find("/material/k1: missing"), std::string::npos);
}

struct BadValue {
  const char* pointer;
  json value;
  const char* expected;  // part of the message
};

class BadValueTest : public testing::TestWithParam<BadValue> {};

// Stable names (index and field): the default name prints the parameter's bytes, which
// hold heap addresses and so differ between test discovery and the test run.
std::string bad_value_name(const testing::TestParamInfo<BadValue>& info) {
  std::string name = std::to_string(info.index);
  for (const char* c = info.param.pointer; *c; ++c) {
    name += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
  }
  return name;
}

TEST_P(BadValueTest, IsRejectedNamingTheFieldAndWhatWasExpected) {
  const BadValue& bad = GetParam();
  json j = block5_json();
  j[json::json_pointer(bad.pointer)] = bad.value;
  std::string file;
  const std::string error = load_error(j, &file);
  EXPECT_NE(error.find(file + ": " + bad.pointer + ": expected"), std::string::npos) << error;
  EXPECT_NE(error.find(bad.expected), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    EveryCheckedField, BadValueTest,
    testing::Values(BadValue{"/material/density", 0.0, "positive"},
                    BadValue{"/material/density", -1200.0, "positive"},
                    BadValue{"/material/c1", -1.0, "non-negative"},
                    BadValue{"/material/c2", "a lot", "number"},
                    BadValue{"/mesh/sx_m", 0.0, "a number from 1e-06 to 10 [m]"},
                    BadValue{"/mesh/sz_m", -0.04, "a number from 1e-06 to 10 [m]"},
                    // Rest lengths of exactly 0 before: "edge 0: L = 0".
                    BadValue{"/mesh/sx_m", 1e-300, "a number from 1e-06 to 10 [m]"},
                    BadValue{"/mesh/sy_m", 1e5, "a number from 1e-06 to 10 [m]"},
                    BadValue{"/mesh/nx", 1, "integer from 2"}, BadValue{"/mesh/nz", 2.5, "integer"},
                    BadValue{"/mesh/dim", 4, "from 2 to 3"},
                    BadValue{"/mesh/structure", "cubic", "\"truss\" or \"lattice\""},
                    BadValue{"/integrator/method", "euler", "semi_implicit_euler"},
                    BadValue{"/integrator/dt_s", 0.0, "positive"},
                    BadValue{"/integrator/mass_scale", -5.0, "positive"},
                    BadValue{"/protocol/depth_mm", 50.0, "below the block height"},
                    BadValue{"/protocol/speed_mm_s", 0.0, "positive"},
                    BadValue{"/protocol/type", "sine", "push_hold_release"},
                    // Edges that hold no tension: failed hundreds of steps later.
                    BadValue{"/material/c2", 0.0, "c2 > 0 (the series damper carries"},
                    // One step of 1 ms ran silently for 1e-7 s.
                    BadValue{"/duration_s", 1e-7, "at least one step of /integrator/dt_s"}),
    bad_value_name);

TEST(BadScenario, ProtocolTimesMustIncreaseStrictly) {
  json j = block5_json();
  j["protocol"] = {{"type", "table"}, {"t_s", {0.0, 1.0, 1.0}}, {"plate_mm", {0.0, 2.0, 0.0}}};
  const std::string error = load_error(j);
  EXPECT_NE(error.find("/protocol/t_s/2: expected strictly increasing"), std::string::npos)
      << error;
}

TEST(BadScenario, ProtocolTableColumnsMustHaveEqualLength) {
  json j = block5_json();
  j["protocol"] = {{"type", "table"}, {"t_s", {0.0, 1.0}}, {"plate_mm", {0.0, 2.0, 0.0}}};
  EXPECT_NE(load_error(j).find("/protocol/plate_mm: expected as many entries"), std::string::npos);
}

TEST(BadScenario, ViscositiesMayNotBothBeZero) {
  json j = block5_json();
  j["material"]["c1"] = 0.0;
  j["material"]["c2"] = 0.0;
  EXPECT_NE(load_error(j).find("/material/c2: expected c1 + c2 > 0"), std::string::npos);
}

TEST(BadScenario, TableProtocolIsAccepted) {
  json j = block5_json();
  j["protocol"] = {{"type", "table"}, {"t_s", {0.0, 1.0, 2.0}}, {"plate_mm", {0.0, 2.0, 0.0}}};
  ScenarioFile f(j.dump());
  const Scenario s = load_scenario(f.path());
  EXPECT_DOUBLE_EQ(s.protocol.displacement_mm(0.5), 1.0);
}

// Every feature of the reference model is reachable from a scenario file: topology
// maintenance, volume preservation and a relaxation spectrum reach the model, and the model
// they build runs and differs from the one without them.
TEST(ScenarioFeatures, TopologyVolumeAndSpectrumKeysReachTheModel) {
  json j = block5_json();
  j["topology_maintenance"] = {{"eps", 0.3}, {"k_n_m", 200.0}, {"c_ns_m", 0.5}};
  j["material"]["volume_kv"] = 2e4;
  j["material"]["spectrum"] = json::array({{{"k", 1e4}, {"c", 50.0}}, {{"k", 5e3}, {"c", 500.0}}});
  ScenarioFile f(j.dump());
  const Scenario s = load_scenario(f.path());
  const Model m = s.build_model();
  EXPECT_TRUE(m.topology.enabled);
  EXPECT_DOUBLE_EQ(m.topology.eps, 0.3);
  EXPECT_DOUBLE_EQ(m.topology.k, 200.0);
  EXPECT_DOUBLE_EQ(m.topology.c, 0.5);
  EXPECT_TRUE(m.volume.enabled);
  EXPECT_DOUBLE_EQ(m.volume.kv, 2e4);
  ASSERT_EQ(m.materials.front().spectrum_arms, 2);
  // Moduli are mapped to edges like k2 (sim/mesh.hpp): the ratio of the arms stays.
  EXPECT_NEAR(m.materials.front().spectrum[0].k / m.materials.front().spectrum[1].k, 2.0, 1e-12);
  EXPECT_GT(m.materials.front().spectrum[0].k, 0.0);

  const Model plain = load_scenario("block5").build_model();
  Simulator with(m, s.options), without(plain, s.options);
  double max_diff = 0.0;
  for (long step = 1; step <= 2000; ++step) {
    const double fw = with.step(s.plate_z(m, step)).plate_force_N;
    const double fo = without.step(s.plate_z(plain, step)).plate_force_N;
    ASSERT_TRUE(std::isfinite(fw));
    max_diff = std::max(max_diff, std::fabs(fw - fo));
  }
  EXPECT_GT(max_diff, 0.0);
}

// "masses": "stable_step" gives every particle the fits' object-model mass for the step
// (sim/stable_masses.hpp) and no gravity; the density and a mass scale are then refused.
TEST(ScenarioFeatures, StableStepMassesAreTheRuleTheFitsUseAndExcludeDensityAndMassScale) {
  json j = block5_json();
  j["integrator"].erase("mass_scale");
  j["integrator"]["masses"] = "stable_step";
  j["material"].erase("density");
  ScenarioFile f(j.dump());
  const Scenario s = load_scenario(f.path());
  const Model m = s.build_model();
  Model expected = m;
  assign_stable_step_masses(expected, s.options.dt);
  ASSERT_EQ(m.mass.size(), expected.mass.size());
  for (std::size_t i = 0; i < m.mass.size(); ++i) EXPECT_EQ(m.mass[i], expected.mass[i]) << i;
  EXPECT_EQ(m.gravity, Vec3::Zero());
  EXPECT_EQ(m.mass_scale, 1.0);
  // The stable-step masses pass the scenario's own stability check by construction.
  EXPECT_LT(s.options.dt, max_stable_dt(m, s.options.integrator));
  Simulator sim(m, s.options);
  for (long step = 1; step <= 2000; ++step) ASSERT_TRUE(std::isfinite(sim.step(s.plate_z(m, step)).plate_force_N));

  json with_density = j;
  with_density["material"]["density"] = 1800.0;
  EXPECT_NE(load_error(with_density).find("/material/density: expected no density"), std::string::npos)
      << load_error(with_density);
  json with_scale = j;
  with_scale["integrator"]["mass_scale"] = 100.0;
  EXPECT_NE(load_error(with_scale).find("/integrator/mass_scale: expected no mass_scale"),
            std::string::npos)
      << load_error(with_scale);
  json without_density = block5_json();
  without_density["material"].erase("density");
  EXPECT_NE(load_error(without_density).find("/material/density: missing"), std::string::npos)
      << load_error(without_density);
}

INSTANTIATE_TEST_SUITE_P(
    FeatureFields, BadValueTest,
    testing::Values(BadValue{"/topology_maintenance/eps", 1.5, "(0, 1]"},
                    BadValue{"/topology_maintenance", 3.0, "an object"},
                    BadValue{"/material/volume_kv", 0.0, "positive"},
                    BadValue{"/material/spectrum", json::array(), "an array of 1 to 8"}),
    bad_value_name);

TEST(BadScenario, ASpectrumArmWithANegativeModulusIsNamed) {
  json j = block5_json();
  j["material"]["spectrum"] = json::array({{{"k", 1e4}, {"c", 1.0}}, {{"k", -1.0}, {"c", 1.0}}});
  const std::string error = load_error(j);
  EXPECT_NE(error.find("/material/spectrum/1/k: expected a positive"), std::string::npos) << error;
}

TEST(BadScenario, TopologyMaintenanceNeedsASpringOrADamper) {
  json j = block5_json();
  j["topology_maintenance"] = {{"eps", 0.2}, {"k_n_m", 0.0}, {"c_ns_m", 0.0}};
  const std::string error = load_error(j);
  EXPECT_NE(error.find("/topology_maintenance/k_n_m"), std::string::npos) << error;
}

TEST(BadScenario, UnstableTimeStepIsRefusedWithTheLargestSafeDt) {
  json j = block5_json();
  j["integrator"]["dt_s"] = 0.1;
  ScenarioFile f(j.dump());
  const Scenario s = load_scenario(f.path());
  try {
    Simulator sim(s.build_model(), s.options);
    FAIL() << "dt 0.1 s accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("largest safe dt"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rheo
