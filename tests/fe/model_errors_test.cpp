// Every bad input to the continuum model, and every numerical failure, is a rheo::Error that
// names the parameter (or the failure) and what was expected; a failed step leaves the state
// of the step before.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "fe/fe_model.hpp"
#include "sim/error.hpp"
#include "tests/fe/error_message.hpp"

namespace rheo::fe {
namespace {

bool has(const std::string& m, const char* s) { return m.find(s) != std::string::npos; }

ViscoelasticLaw elastic(double gamma = 0.35) { return ViscoelasticLaw::elastic(4.0e4, gamma); }

ModelOptions with(Formulation f) {
  ModelOptions o;
  o.formulation = f;
  o.thickness_m = 0.0125;
  return o;
}

TEST(FeModelErrors, PoissonRatioHalfOnlyInPlaneStress) {
  std::string m = message_of([] {
    ContinuumModel(make_rectangle(1, 1, 2, 2), elastic(0.5), with(Formulation::kPlaneStrain));
  });
  EXPECT_TRUE(has(m, "Poisson ratio gamma = 0.5") && has(m, "-1 < gamma < 0.5")) << m;
  m = message_of([] {
    ContinuumModel(make_box(1, 1, 1, 1, 1, 1), elastic(0.5), with(Formulation::kSolid));
  });
  EXPECT_TRUE(has(m, "Poisson ratio") && has(m, "solid")) << m;
  EXPECT_EQ(message_of([] {
              ContinuumModel(make_rectangle(1, 1, 2, 2), elastic(0.5),
                             with(Formulation::kPlaneStress));
            }),
            "no error");
}

TEST(FeModelErrors, OptionsAndMeshAreNamed) {
  ModelOptions o = with(Formulation::kPlaneStress);
  o.thickness_m = 0.0;
  std::string m = message_of([&] { ContinuumModel(make_rectangle(1, 1, 2, 2), elastic(), o); });
  EXPECT_TRUE(has(m, "thickness = 0") && has(m, "positive")) << m;
  m = message_of([] {
    ContinuumModel(make_rectangle(1, 1, 2, 2), elastic(), with(Formulation::kSolid));
  });
  EXPECT_TRUE(has(m, "mesh dim = 2") && has(m, "expected 3")) << m;
  o = with(Formulation::kPlaneStress);
  o.max_contact_iterations = 0;
  m = message_of([&] { ContinuumModel(make_rectangle(1, 1, 2, 2), elastic(), o); });
  EXPECT_TRUE(has(m, "max_contact_iterations = 0") && has(m, "at least 1")) << m;
  Mesh bad = make_rectangle(1, 1, 2, 2);
  std::swap(bad.elements[3][0], bad.elements[3][1]);  // clockwise
  m = message_of([&] { ContinuumModel(bad, elastic(), with(Formulation::kPlaneStress)); });
  EXPECT_TRUE(has(m, "element 3") && has(m, "rest area")) << m;
  m = message_of([] { make_rectangle(1, 1, 0, 3); });
  EXPECT_TRUE(has(m, "nx = 0") && has(m, "at least 1")) << m;
}

TEST(FeModelErrors, StepInputsAreNamed) {
  ContinuumModel model(make_rectangle(1, 1, 2, 2), elastic(), with(Formulation::kPlaneStress));
  std::string m = message_of([&] { model.step(0.0, 0.01); });
  EXPECT_TRUE(has(m, "time step dt = 0") && has(m, "positive")) << m;
  m = message_of([&] { model.step(-1.0, 0.01); });
  EXPECT_TRUE(has(m, "time step dt = -1")) << m;
  m = message_of([&] { model.step(0.1, NAN); });
  EXPECT_TRUE(has(m, "plate depth") && has(m, "finite")) << m;
  EXPECT_EQ(model.time_s(), 0.0);
  m = message_of([] { push_hold_release(0.0, 1e-3, 1.0, 1e-3, 1.0); });
  EXPECT_TRUE(has(m, "push_speed_m_s = 0")) << m;
  m = message_of([] { push_hold_release(1e-3, 1e-3, -1.0, 1e-3, 1.0); });
  EXPECT_TRUE(has(m, "hold_s = -1") && has(m, ">= 0")) << m;
}

TEST(FeModelErrors, InvertedElementsAreReportedNotReturned) {
  // Pushed 1.5 times its height in one step, the small-strain block turns inside out.
  ContinuumModel model(make_rectangle(1, 1, 2, 2), elastic(), with(Formulation::kPlaneStress));
  model.step(0.1, 0.01);
  const double F = model.plate_force_N();
  const std::string m = message_of([&] { model.step(0.1, 1.5); });
  EXPECT_TRUE(has(m, "inverted") && has(m, "t = 0.2 s")) << m;
  EXPECT_EQ(model.time_s(), 0.1);
  EXPECT_EQ(model.plate_force_N(), F);
  ContinuumModel solid(make_box(1, 1, 1, 1, 1, 1), elastic(), with(Formulation::kSolid));
  EXPECT_TRUE(has(message_of([&] { solid.step(0.1, 1.5); }), "volume"));
}

TEST(FeModelErrors, SingularStiffnessIsAFailedFactorisation) {
  // A node that no element holds leaves a zero row: a rigid motion the constraints do not fix.
  Mesh m = make_rectangle(1, 1, 2, 2);
  m.nodes.conservativeResize(2, m.node_count() + 1);
  m.nodes.col(m.node_count() - 1) << 0.5, 0.5;
  ContinuumModel model(m, elastic(), with(Formulation::kPlaneStress));
  const std::string msg = message_of([&] { model.step(0.1, 0.01); });
  EXPECT_TRUE(has(msg, "factorisation failed") && has(msg, "rigid motion")) << msg;
}

TEST(FeModelErrors, OverflowIsAnErrorNotANumber) {
  // E = 1e300 Pa on a 1e10 m thick slab: the stiffness overflows to infinity.
  ModelOptions o = with(Formulation::kPlaneStress);
  o.thickness_m = 1e10;
  ContinuumModel model(make_rectangle(1, 1, 2, 2), ViscoelasticLaw::elastic(1e300, 0.3), o);
  const std::string msg = message_of([&] { model.step(0.1, 0.01); });
  EXPECT_TRUE(has(msg, "factorisation failed") || has(msg, "non-finite")) << msg;
}

}  // namespace
}  // namespace rheo::fe
