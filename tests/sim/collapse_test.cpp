// A collapse is never a result: the element watch (an inverted triangle or tetrahedron fails
// the run on every CPU path), the hold watch (an object giving way under a held plate), and
// the plate grip that keeps clay_push's lattice from buckling in a long hold, whose force
// then relaxes as the material itself does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "sim/element_watch.hpp"
#include "sim/error.hpp"
#include "sim/fast/fast_simulator.hpp"
#include "sim/hold_watch.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"
#include "tests/test_paths.hpp"

namespace rheo {
namespace {

// The first two vertices of the first element with no fixed vertex (a fixed particle goes
// back to its rest position every step) swap places: that element turns inside out.
std::vector<Vec3> with_an_element_inverted(const Model& model) {
  std::vector<Vec3> x = model.x0;
  const std::size_t count = model.dim == 2 ? model.triangles.size() : model.tetrahedra.size();
  for (std::size_t el = 0; el < count; ++el) {
    const int nv = model.dim == 2 ? 3 : 4;
    auto vertex = [&](int k) {
      return model.dim == 2 ? model.triangles[el][static_cast<std::size_t>(k)]
                            : model.tetrahedra[el][static_cast<std::size_t>(k)];
    };
    bool free = true;
    for (int k = 0; k < nv; ++k) free = free && model.flags[static_cast<std::size_t>(vertex(k))] != kFixed;
    if (!free) continue;
    std::swap(x[static_cast<std::size_t>(vertex(0))], x[static_cast<std::size_t>(vertex(1))]);
    return x;
  }
  ADD_FAILURE() << "no element without a fixed vertex";
  return x;
}

Scenario block5_2d() {
  Scenario s = load_scenario("block5");
  s.block.dim = 2;
  s.block.ny = 1;
  return s;
}

// The 3-D lattice clay_push was before it became the fits' object model: 5 x 2 x 5
// particles, mass scaling and a gripping plate (data/scenarios/clay_push_lattice3d.json).
Scenario lattice3d_clay() {
  return load_scenario(std::string(RHEO_SOURCE_DIR) + "/data/scenarios/clay_push_lattice3d.json");
}

TEST(ElementWatch, NamesTheInvertedTetrahedronItsParticlesPlaceAndTime) {
  const Model model = lattice3d_clay().build_model();
  const ElementWatch watch(model);
  ASSERT_FALSE(watch.empty());
  EXPECT_EQ(watch.find_inverted(model.x0, 0.0), "");
  const std::string what = watch.find_inverted(with_an_element_inverted(model), 1.5);
  EXPECT_NE(what.find("the mesh collapsed at t = 1.5 s: tetrahedron "),
            std::string::npos) << what;
  EXPECT_NE(what.find("turned inside out (signed volume -"), std::string::npos) << what;
  EXPECT_NE(what.find(" m^3 at rest)"), std::string::npos) << what;
  EXPECT_THROW(watch.check(with_an_element_inverted(model), 1.5), Error);
}

TEST(ElementWatch, NamesTheInvertedTriangleIn2D) {
  const Model model = block5_2d().build_model();
  ASSERT_EQ(model.dim, 2);
  const ElementWatch watch(model);
  EXPECT_EQ(watch.find_inverted(model.x0, 0.0), "");
  const std::string what = watch.find_inverted(with_an_element_inverted(model), 0.25);
  EXPECT_NE(what.find(": triangle "), std::string::npos) << what;
  EXPECT_NE(what.find("signed area"), std::string::npos) << what;
}

TEST(ElementWatch, AModelWithoutElementsHasNothingToWatch) {
  Model model = load_scenario("block5").build_model();
  model.tetrahedra.clear();
  const ElementWatch watch(model);
  EXPECT_TRUE(watch.empty());
  EXPECT_NO_THROW(watch.check(with_an_element_inverted(load_scenario("block5").build_model()), 0));
}

TEST(ElementWatch, TheReferenceSimulatorFailsOnAnInvertedElement) {
  for (const Scenario& s : {load_scenario("block5"), block5_2d()}) {
    const Model model = s.build_model();
    Simulator sim(model, s.options);
    sim.mutable_state().x = with_an_element_inverted(model);
    try {
      sim.step(model.height);
      ADD_FAILURE() << "an inverted element passed";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the mesh collapsed at t = "), std::string::npos)
          << e.what();
    }
  }
}

TEST(ElementWatch, TheFastPathFailsOnAnInvertedElement) {
  const Scenario s = load_scenario("block5");
  const Model model = s.build_model();
  fast::FastSimulator sim(model, s.options, 1);
  State state = initial_state(model);
  state.x = with_an_element_inverted(model);
  sim.set_state(state);
  const std::vector<double> plate(10, model.height);
  try {
    sim.run(plate);
    ADD_FAILURE() << "an inverted element passed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has turned inside out"), std::string::npos) << e.what();
  }
}

// Every particle moving at `speed` [m/s] along x.
State moving(const Model& model, double speed) {
  State s = initial_state(model);
  for (Vec3& v : s.v) v = Vec3(speed, 0.0, 0.0);
  return s;
}

TEST(HoldWatch, FailsWhenTheObjectSpeedsUpUnderAHeldPlateAndNamesTheParticle) {
  const Model model = load_scenario("block5").build_model();
  HoldWatch watch(model);
  EXPECT_EQ(watch.observe(0.0, 0.0, 0.0, moving(model, 0.0)), "");
  EXPECT_EQ(watch.observe(1.0, 1.0, 5.0, moving(model, 1e-3)), "");  // the plate moved
  EXPECT_EQ(watch.observe(2.0, 1.0, 5.0, moving(model, 1e-4)), "");  // held: coming to rest
  EXPECT_EQ(watch.observe(3.0, 1.0, 5.0, moving(model, 3e-3)), "");  // 9 times: passes
  const std::string what = watch.observe(4.0, 1.0, 5.0, moving(model, 4e-3));  // 16 times
  EXPECT_NE(what.find("the object gave way under the held plate at t = 4 s"), std::string::npos)
      << what;
  EXPECT_NE(what.find("particle 0 near ("), std::string::npos) << what;
  EXPECT_NE(what.find("moves at 4 mm/s"), std::string::npos) << what;
}

TEST(HoldWatch, JudgesNothingBeforeThePlateMovedNorWhenThePlateNoLongerPresses) {
  const Model model = load_scenario("block5").build_model();
  HoldWatch watch(model);
  // Settling under gravity before the plate moves: no plate-driven energy to compare with.
  EXPECT_EQ(watch.observe(0.0, 0.0, 1.0, moving(model, 0.0)), "");
  EXPECT_EQ(watch.observe(1.0, 0.0, 1.0, moving(model, 1e-2)), "");
  EXPECT_EQ(watch.observe(2.0, 2.0, 1.0, moving(model, 1e-5)), "");
  // Released: the object springs back freely, the plate does not press.
  EXPECT_EQ(watch.observe(3.0, 2.0, 0.0, moving(model, 1e-2)), "");
}

// Largest lateral distance of a plate particle from its rest position after `seconds` of
// clay_push_lattice3d's push (the 3-D lattice with a gripping plate), on the reference or the
// fast path.
double plate_particles_lateral_slip(bool grip, bool fast_path, double seconds) {
  Scenario s = lattice3d_clay();
  s.plate_grip = grip;
  const Model model = s.build_model();
  const long long steps = std::llround(seconds / s.options.dt);
  std::vector<double> plate;
  for (long long i = 1; i <= steps; ++i) plate.push_back(s.plate_z(model, i));
  State end;
  if (fast_path) {
    fast::FastSimulator sim(model, s.options, 1);
    sim.run(plate);
    end = sim.state();
  } else {
    Simulator sim(model, s.options);
    for (double z : plate) sim.step(z);
    end = sim.state();
  }
  double slip = 0.0;
  for (int i = 0; i < model.num_particles(); ++i) {
    if (model.flags[static_cast<std::size_t>(i)] != kPlate) continue;
    const Vec3 d = end.x[static_cast<std::size_t>(i)] - model.x0[static_cast<std::size_t>(i)];
    slip = std::max(slip, std::hypot(d.x(), d.y()));
  }
  return slip;
}

TEST(PlateGrip, AHeldParticleDoesNotSlideAlongThePlateOnTheReferenceAndTheFastPath) {
  ASSERT_TRUE(lattice3d_clay().plate_grip);
  for (const bool fast_path : {false, true}) {
    // Without grip the top spreads sideways as it is pressed (Poisson).
    // Without grip the top spreads sideways as it is pressed (Poisson): 0.38 mm in 5 s. With
    // it the top particles slide only in the steps the plate does not hold them (under
    // clay_push's penetration rule, a step whose update does not reach the plate): 0.04 mm.
    const double free_slip = plate_particles_lateral_slip(false, fast_path, 5.0);
    const double gripped_slip = plate_particles_lateral_slip(true, fast_path, 5.0);
    EXPECT_GT(free_slip, 1e-4) << fast_path;
    EXPECT_LT(gripped_slip, 0.2 * free_slip) << fast_path;
  }
}

// The stress of one edge of the material under the same nominal strain history (a ramp at
// `rate` [1/s] for t_push, then held), by integrating the edge's own equations directly:
// Voigt d' = (c2 e' - k1 d) / (c1 + c2), T = k1 d + c1 d' ; arm m' = e' - (k2/c3) m, T += k2 m.
double material_stress(const EdgeMaterial& mat, double rate, double t_push, double t) {
  const double h = 1e-4;
  double d = 0.0, m = 0.0, stress = 0.0;
  for (double time = 0.0; time < t - 0.5 * h; time += h) {
    const double e_dot = time < t_push ? rate : 0.0;
    const double d_dot = (mat.c2 * e_dot - mat.k1 * d) / (mat.c1 + mat.c2);
    d += h * d_dot;
    m += h * (e_dot - mat.k2 / mat.c3 * m);
    stress = mat.k1 * d + mat.c1 * d_dot + mat.k2 * m;
  }
  return stress;
}

TEST(Collapse, ClayPushHeld200sRelaxesAsItsMaterialDoes) {
  Scenario s = load_scenario("clay_push");
  const double depth_mm = 9.6, speed = 0.5, hold = 200.0;
  s.protocol = PlateProtocol::push_hold_release(depth_mm, speed, hold, 0.0);
  const Model model = s.build_model();
  const double t_push = depth_mm / speed;
  const long long steps = std::llround((t_push + hold) / s.options.dt);
  std::vector<double> plate;
  for (long long i = 1; i <= steps; ++i) plate.push_back(s.plate_z(model, i));
  fast::FastSimulator sim(model, s.options, 1);
  const std::vector<StepReport> r = sim.run(plate);  // throws if an element inverts
  auto force_at = [&](double t) {
    return r[static_cast<std::size_t>(std::llround(t / s.options.dt)) - 1].plate_force_N;
  };
  const EdgeMaterial& mat = s.block.material;
  const double rate = speed / (model.height * 1e3);
  const double f_push = force_at(t_push);
  const double m_push = material_stress(mat, rate, t_push, t_push);
  ASSERT_GT(f_push, 5.0);
  for (const double after : {10.0, 30.0, 60.0, 100.0, 150.0, 200.0}) {
    const double lattice = force_at(t_push + after) / f_push;
    const double material = material_stress(mat, rate, t_push, t_push + after) / m_push;
    EXPECT_NEAR(lattice, material, 0.04) << after << " s into the hold";
  }
  // The force never leaves the plate during the hold.
  for (long long i = std::llround((t_push + 1.0) / s.options.dt); i < steps; ++i) {
    ASSERT_GT(r[static_cast<std::size_t>(i)].plate_force_N, 0.2 * f_push) << "step " << i;
  }
}

}  // namespace
}  // namespace rheo
