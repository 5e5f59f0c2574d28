// Bit-exact cosimulation of the RTL cores with the tool unit (ToolContact = 1) against the
// bit-true model, through the Backend interface with the tool's pose every step: the
// built-in indent_sphere scene at one and two lanes (random stream stalls on one of them),
// a plate and a turning roller pressed into the same dough, and with Coulomb friction: a
// sphere dragged sideways through the dough and the built-in roller_dough (seed 000
// Fig. 2.24, a turning roller with mu = 0.5). Every particle word and the
// tool's reaction force every step must be equal; the cycles per step must equal the
// formula (MPM drain longer by the tool unit); the fixed-point reaction must follow the
// double reference, and the tool must move the dough by far more than that error (it could
// not be silently missing).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/cosim/cosim.hpp"
#include "host/driver/core_image.hpp"
#include "sim/scenario.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimResult;

constexpr double kMaxPositionErrorRel = 2e-5;
constexpr double kMaxToolForceErrorRel = 2e-3;

CosimResult expect_exact(const Scenario& scenario, int lanes, long steps, double stall = 0.0) {
  const Model model = scenario.build_model();
  EXPECT_EQ(edge_element_for(model), hls::kThreeElementWithTool);
  cosim::CosimOptions opt;
  opt.steps = steps;
  opt.lanes = lanes;
  opt.compare_every = 10;
  opt.input_idle_prob = stall;
  opt.output_stall_prob = stall;
  const CosimResult r = cosim::run_cosim(scenario, opt);
  EXPECT_EQ(r.element, hls::kThreeElementWithTool.name);
  EXPECT_EQ(r.steps, steps);
  EXPECT_EQ(r.mismatches, 0) << scenario.name << ", " << lanes
                             << " lanes: " << (r.first.empty() ? "" : r.first.front().describe());
  EXPECT_EQ(r.cycles_per_step_formula,
            cycles_per_step_formula(r.edge_rows, r.particles, lanes, hls::kThreeElementWithTool));
  EXPECT_DOUBLE_EQ(r.cycles_per_step_measured, double(r.cycles_per_step_formula));
  EXPECT_LE(r.max_pos_err_rel, kMaxPositionErrorRel);
  EXPECT_LE(r.max_tool_force_err_rel, kMaxToolForceErrorRel);
  EXPECT_LE(r.median_tool_force_err_rel, r.max_tool_force_err_rel);
  EXPECT_GE(r.max_tool_force_err_step, 1);
  EXPECT_LE(r.max_tool_force_err_step, steps);
  // the tool pushes: a reaction of a good fraction of a newton
  EXPECT_GT(r.max_tool_force_ref_N, 0.3) << scenario.name;
  std::printf("%s, %d lane(s): %ld steps, %ld mismatches, %.0f cycles/step (formula %ld), "
              "tool reaction peak %.3f N, fixed vs double %.2e of it (median %.2e), "
              "positions %.2e\n",
              scenario.name.c_str(), lanes, r.steps, r.mismatches, r.cycles_per_step_measured,
              r.cycles_per_step_formula, r.max_tool_force_ref_N, r.max_tool_force_err_rel,
              r.median_tool_force_err_rel, r.max_pos_err_rel);
  return r;
}

TEST(ToolCosim, IndentSphereIsBitExactAtOneAndTwoLanes) {
  const Scenario s = load_scenario("indent_sphere");
  expect_exact(s, 1, 1200);
  expect_exact(s, 2, 1200, 0.2);  // with random idle input and back-pressure
}

TEST(ToolCosim, APlateAndATurningRollerAreBitExact) {
  Scenario plate = load_scenario("indent_sphere");
  plate.name = "indent_plate";
  plate.tools[0].shape = ToolShape::kPlane;
  plate.tools[0].axis = Vec3(0.0, 0.3, -1.0).normalized();  // a tilted plate from above
  // Its lowest point over the 60 mm block (0.3 x 30 mm below its centre) starts 1.5 mm above
  // the top surface. Placed at the sphere's bottom itself, the plate would start 9 mm deep
  // in one side, and the jolt turns a tetrahedron inside out at 15 ms (still at 5 and 7 mm
  // deep), which the reference now refuses (sim/element_watch.hpp). 1,200 steps: it presses
  // 8 mm, as the sphere does.
  for (ToolPose& p : plate.tool_paths[0].pose) p.position.z() -= 0.012 - 0.0105;
  expect_exact(plate, 1, 1200);

  Scenario roller = load_scenario("indent_sphere");
  roller.name = "indent_roller";
  Tool& t = roller.tools[0];
  t.shape = ToolShape::kCylinder;
  t.axis = Vec3(0.0, 1.0, 0.0);
  t.length = 0.04;
  t.radius = 0.01;
  for (std::size_t k = 0; k < roller.tool_paths[0].pose.size(); ++k) {
    ToolPose& p = roller.tool_paths[0].pose[k];
    p.position.z() -= 0.012 - 0.0105;  // its bottom where the sphere's was
    p.position.x() += 0.01 * double(k) / 4.0;  // it rolls along x while it presses
    p.q = 2.0 * double(k);
  }
  expect_exact(roller, 1, 600);
}

TEST(ToolCosim, FrictionADraggedSphereAndTheRollerFormingDoughAreBitExact) {
  // indent_sphere's sphere with mu = 0.4: down 6 mm in 0.3 s, then dragged 12 mm along x.
  Scenario drag = load_scenario("indent_sphere");
  drag.name = "drag_sphere";
  drag.tools[0].contact.mu = 0.4;
  ToolPath& path = drag.tool_paths[0];
  const Vec3 top = path.pose.front().position;
  path.t = {0.0, 0.3, 0.6};
  path.pose.assign(3, ToolPose{});
  path.pose[0].position = top;
  path.pose[1].position = top - Vec3(0.0, 0.0, 0.006);
  path.pose[2].position = path.pose[1].position + Vec3(0.012, 0.0, 0.0);
  expect_exact(drag, 1, 600);

  // roller_dough: down in 1 s, then rolling (and turning) along x; 1,300 steps at two
  // lanes with random stalls.
  const Scenario roller = load_scenario("roller_dough");
  ASSERT_GT(roller.tools[0].contact.mu, 0.0);
  expect_exact(roller, 2, 1300, 0.2);
}

}  // namespace
}  // namespace rheo::driver
