// Contact among objects and tool contact (sim/contact.hpp, sim/tool.hpp): the laws the
// penalty method must keep, checked against what physics says independently of the code.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo {
namespace {

// A stiff, nearly elastic 10 mm cube (2 x 2 x 2 particles; a_min = a_max = 1 makes every edge
// a pure Voigt element) as a scenario object.
std::string cube_json(int n = 2, double size = 0.01) {
  const std::string s = std::to_string(size);
  return R"({"dim": 3, "structure": "lattice", "nx": )" + std::to_string(n) +
         R"(, "ny": )" + std::to_string(n) + R"(, "nz": )" + std::to_string(n) +
         R"(, "sx_m": )" + s + R"(, "sy_m": )" + s + R"(, "sz_m": )" + s +
         R"(, "fix_bottom": false, "plate_top": false})";
}
const char* kStiff = R"({"density": 1000, "k1": 1e6, "c1": 100, "c2": 1e6, "a_min": 1, "a_max": 1})";

Scenario scene(const std::string& extra, int n = 2) {
  return parse_scenario(R"({"name": "t", "mesh": )" + cube_json(n) + R"(, "material": )" +
                            kStiff +
                            R"(, "integrator": {"method": "semi_implicit_euler", "dt_s": 1e-5},
         "protocol": {"type": "none"}, "duration_s": 1)" +
                            extra + "}",
                        "test scene");
}

SimOptions half_bound(const Model& m) {
  SimOptions o;
  o.dt = 0.5 * max_stable_dt(m, Integrator::kSemiImplicitEuler);
  return o;
}

Vec3 momentum(const Model& m, const State& s) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < m.num_particles(); ++i) p += m.mass[i] * s.v[i];
  return p;
}

Vec3 centre_of_mass(const Model& m, const State& s, int object) {
  Vec3 x = Vec3::Zero();
  double mass = 0.0;
  for (int i = 0; i < m.num_particles(); ++i) {
    if (!m.object.empty() && m.object[i] != object) continue;
    x += m.mass[i] * s.x[i];
    mass += m.mass[i];
  }
  return x / mass;
}

// Distance from p to triangle abc (brute force: the plane or the nearest edge).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a).normalized();
  const double d = n.dot(p - a);
  const Vec3 f = p - d * n;
  const bool inside = (b - a).cross(f - a).dot(n) >= 0 && (c - b).cross(f - b).dot(n) >= 0 &&
                      (a - c).cross(f - c).dot(n) >= 0;
  if (inside) return std::abs(d);
  auto segment = [&](const Vec3& u, const Vec3& v) {
    const double t = std::clamp((p - u).dot(v - u) / (v - u).squaredNorm(), 0.0, 1.0);
    return (p - (u + t * (v - u))).norm();
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// How deep any particle of one object lies inside another object: for a particle inside a
// tetrahedron of another object, its distance to that object's surface. 0 when none is.
double deepest_penetration(const Model& m, const State& s) {
  std::map<std::array<int, 3>, int> count;
  for (const auto& t : m.tetrahedra) {
    for (int opposite = 0; opposite < 4; ++opposite) {
      std::array<int, 3> f;
      int k = 0;
      for (int v = 0; v < 4; ++v) {
        if (v != opposite) f[k++] = t[v];
      }
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  }
  std::vector<std::array<int, 3>> surface;
  for (const auto& [f, c] : count) {
    if (c == 1) surface.push_back(f);
  }
  double deepest = 0.0;
  for (int p = 0; p < m.num_particles(); ++p) {
    for (const auto& t : m.tetrahedra) {
      if (m.object[t[0]] == m.object[p]) continue;
      Eigen::Matrix3d A;
      for (int c = 0; c < 3; ++c) A.col(c) = s.x[t[c + 1]] - s.x[t[0]];
      const Vec3 w = A.inverse() * (s.x[p] - s.x[t[0]]);
      if (w.minCoeff() < 0.0 || w.sum() > 1.0) continue;
      double depth = 1e300;
      for (const auto& f : surface) {
        if (m.object[f[0]] != m.object[t[0]]) continue;
        depth = std::min(depth, point_triangle_distance(s.x[p], s.x[f[0]], s.x[f[1]], s.x[f[2]]));
      }
      deepest = std::max(deepest, depth);
    }
  }
  return deepest;
}

TEST(ToolContact, BlockSlidingOnAPlaneStopsWhereCoulombSays) {
  // v0^2 / (2 mu g): the kinetic friction law's stopping distance of a rigid block.
  const double mu = 0.3, v0 = 0.1, g = 9.81, eps = 1e-4, k = 2000.0;
  Scenario s = scene(R"(, "velocity_m_s": [0.1, 0, 0],
      "tools": [{"name": "ground", "shape": "plane",
                 "contact": {"eps_m": 1e-4, "k_n_m": 2000, "c_ns_m": 0.5, "mu": 0.3},
                 "path": {"t_s": [0], "position_m": [[0, 0, 0]]}}])");
  Model m = s.build_model();
  // Start at the resting height: each bottom particle carries a quarter of the weight.
  const double sink = 0.25 * 8 * m.mass[0] * g / k;
  for (Vec3& p : m.x0) p.z() += eps - sink;
  s.options = half_bound(m);
  Simulator sim(m, s.options);
  const std::vector<ToolPose> pose = s.tool_poses(0);
  const double x0 = centre_of_mass(m, sim.state(), 0).x();
  const double expected = v0 * v0 / (2.0 * mu * g);
  const int steps = static_cast<int>(2.0 * v0 / (mu * g) / sim.options().dt);
  for (int i = 0; i < steps; ++i) {
    sim.set_tool_poses(pose);
    sim.step(1.0);
  }
  const double slid = centre_of_mass(m, sim.state(), 0).x() - x0;
  EXPECT_NEAR(slid, expected, 0.03 * expected) << "slid " << slid << " m";
  EXPECT_LT(std::abs(momentum(m, sim.state()).x()), 1e-3 * v0 * 8 * m.mass[0]);
  // The ground carries the weight and the friction pointed forward on it while sliding.
  EXPECT_NEAR(sim.tool_reactions()[0].force.z(), -8 * m.mass[0] * g, 0.02 * 8 * m.mass[0] * g);
}

TEST(ToolContact, WithoutFrictionTheBlockKeepsSliding) {
  Scenario s = scene(R"(, "velocity_m_s": [0.1, 0, 0],
      "tools": [{"name": "ground", "shape": "plane",
                 "contact": {"eps_m": 1e-4, "k_n_m": 2000, "c_ns_m": 0.5, "mu": 0},
                 "path": {"t_s": [0], "position_m": [[0, 0, 0]]}}])");
  Model m = s.build_model();
  for (Vec3& p : m.x0) p.z() += 1e-4;
  s.options = half_bound(m);
  Simulator sim(m, s.options);
  for (int i = 0; i < 2000; ++i) {
    sim.set_tool_poses(s.tool_poses(0));
    sim.step(1.0);
  }
  EXPECT_NEAR(momentum(m, sim.state()).x() / (8 * m.mass[0]), 0.1, 1e-9);
}

// Two cubes meet head-on (offset sideways, so that corners hit faces) without gravity.
struct Collision {
  Model model;
  SimOptions options;
};
Collision head_on(double mu) {
  Scenario s = scene(R"(, "velocity_m_s": [0.5, 0, 0],
      "objects": [{"name": "b", "mesh": )" + cube_json(3, 0.012) + R"(, "material": )" + kStiff +
                     R"(, "offset_m": [0.0115, 0.003, 0.002], "velocity_m_s": [-0.5, 0, 0]}],
      "contact": {"eps_m": 5e-4, "k_n_m": 2000, "c_ns_m": 0, "mu": )" +
                     std::to_string(mu) + "}");
  Collision c{s.build_model(), {}};
  c.model.gravity.setZero();
  c.model.floor = false;
  c.options = half_bound(c.model);
  return c;
}

TEST(ObjectContact, MomentumIsKeptWithoutFriction) {
  Collision c = head_on(0.0);
  Simulator sim(c.model, c.options);
  const Vec3 before = momentum(c.model, sim.state());
  const double scale = 0.5 * c.model.mass[0] * c.model.num_particles();
  int touching = 0;
  double deepest = 0.0;
  for (int i = 0; i < 4000; ++i) {
    touching = std::max(touching, sim.step(1.0).object_contacts);
    if (i % 20 == 0) deepest = std::max(deepest, deepest_penetration(c.model, sim.state()));
  }
  const Vec3 after = momentum(c.model, sim.state());
  EXPECT_GT(touching, 0);
  EXPECT_LT((after - before).norm(), 1e-12 * scale) << after.transpose();
  // They bounced: the first cube moves backwards now.
  Vec3 va = Vec3::Zero();
  for (int i = 0; i < 8; ++i) va += sim.state().v[i] / 8.0;
  EXPECT_LT(va.x(), 0.0);
  // No particle went through the threshold into the other cube.
  EXPECT_LT(deepest, c.model.contact.penalty.eps);
}

TEST(ObjectContact, FrictionKeepsLinearMomentumToo) {
  Collision c = head_on(0.5);
  Simulator sim(c.model, c.options);
  const Vec3 before = momentum(c.model, sim.state());
  for (int i = 0; i < 4000; ++i) sim.step(1.0);
  const double scale = 0.5 * c.model.mass[0] * c.model.num_particles();
  EXPECT_LT((momentum(c.model, sim.state()) - before).norm(), 1e-12 * scale);
}

TEST(ToolContact, ReactionIsWhatTheObjectGains) {
  // A sphere driven into a floating cube: per step, the cube's momentum changes by exactly
  // -dt times the reaction on the sphere (edge forces cancel in pairs).
  Scenario s = scene(R"(, "tools": [{"name": "ball", "shape": "sphere", "radius_m": 0.004,
      "contact": {"eps_m": 2e-4, "k_n_m": 500, "c_ns_m": 0.1, "mu": 0.4},
      "path": {"t_s": [0, 0.1], "position_m": [[0.005, 0.005, 0.0145], [0.0055, 0.005, 0.0125]]}}])",
                     3);
  Model m = s.build_model();
  m.gravity.setZero();
  m.floor = false;
  s.options = half_bound(m);
  Simulator sim(m, s.options);
  const double dt = sim.options().dt;
  int touched = 0;
  for (long long i = 1; i * dt < 0.1; ++i) {
    const Vec3 before = momentum(m, sim.state());
    sim.set_tool_poses(s.tool_poses(i));
    sim.step(1.0);
    const ToolReaction& r = sim.tool_reactions()[0];
    touched += r.contacts > 0;
    const Vec3 gained = momentum(m, sim.state()) - before;
    ASSERT_LT((gained + dt * r.force).norm(), 1e-9 * dt * r.force.norm() + 1e-18) << "step " << i;
  }
  EXPECT_GT(touched, 10);
}

TEST(ToolContact, SpinningRollerIsBrakedByFriction) {
  // A roller spinning in place on a fixed block: friction opposes the spin (torque about
  // the axis against it) and pushes the block along the surface velocity.
  Scenario s = parse_scenario(R"({"name": "r", "mesh": {"dim": 3, "structure": "lattice",
      "nx": 5, "ny": 3, "nz": 3, "sx_m": 0.04, "sy_m": 0.02, "sz_m": 0.01, "plate_top": false},
      "material": {"density": 1200, "k1": 2e4, "c1": 2e3, "c2": 2e5},
      "integrator": {"method": "semi_implicit_euler", "dt_s": 0.0005, "mass_scale": 300},
      "protocol": {"type": "none"}, "duration_s": 1,
      "tools": [{"name": "roller", "shape": "cylinder", "axis": [0, 1, 0], "radius_m": 0.01,
                 "length_m": 0.04, "contact": {"eps_m": 5e-4, "k_n_m": 2000, "c_ns_m": 2, "mu": 0.5},
                 "path": {"t_s": [0, 1], "position_m": [[0.02, 0.01, 0.0198], [0.02, 0.01, 0.0198]],
                          "q": [0, 5]}}]})",
                              "roller test");
  const Model m = s.build_model();
  Simulator sim(m, s.options);
  for (long long i = 1; i <= 1000; ++i) {
    sim.set_tool_poses(s.tool_poses(i));
    sim.step(1.0);
  }
  const ToolReaction& r = sim.tool_reactions()[0];
  ASSERT_GT(r.contacts, 0);
  EXPECT_GT(r.force.z(), 0.0);   // the block pushes the roller up
  EXPECT_LT(r.torque.y(), 0.0);  // against the spin (+y)
  // Spin +y: the roller's bottom moves towards -x, and drags the block's top along.
  EXPECT_GT(r.force.x(), 0.0);
}

TEST(ToolContact, GripperLiftsABlockOnlyWithFriction) {
  auto lift = [](double mu) {
    const std::string grip = R"(, "tools": [
        {"name": "ground", "shape": "plane", "contact": {"eps_m": 1e-4, "k_n_m": 2000, "c_ns_m": 0.5},
         "path": {"t_s": [0], "position_m": [[0, 0, 0]]}},
        {"name": "gripper", "shape": "gripper", "axis": [1, 0, 0], "up": [0, 0, 1],
         "length_m": 0.012, "width_m": 0.02, "thickness_m": 0.003,
         "contact": {"eps_m": 1e-4, "k_n_m": 2000, "c_ns_m": 0.5, "mu": )" +
                             std::to_string(mu) + R"(},
         "path": {"t_s": [0, 0.05, 0.1, 0.2], "position_m": [[0.005, 0.005, 0.006], [0.005, 0.005, 0.006],
                  [0.005, 0.005, 0.006], [0.005, 0.005, 0.016]], "q": [0.0104, 0.0104, 0.0096, 0.0096]}}])";
    Scenario s = scene(grip);
    Model m = s.build_model();
    for (Vec3& p : m.x0) p.z() += 1e-4;
    s.options = half_bound(m);
  Simulator sim(m, s.options);
    const double z0 = centre_of_mass(m, sim.state(), 0).z();
    for (long long i = 1; i * sim.options().dt < 0.3; ++i) {
      sim.set_tool_poses(s.tool_poses(i));
      sim.step(1.0);
    }
    return centre_of_mass(m, sim.state(), 0).z() - z0;
  };
  EXPECT_NEAR(lift(0.8), 0.01, 0.001);  // held by friction, lifted with the gripper
  EXPECT_LT(lift(0.0), 0.001);          // slips out and stays on the ground
}

TEST(ObjectContact, SixObjectsSceneNeverPenetratesBeyondTheThreshold) {
  const Scenario s = load_scenario("six_objects");
  const Model m = s.build_model();
  Simulator sim(m, s.options);
  double deepest = 0.0;
  // The first three seconds: every cube has landed (the highest after about 2.5 s).
  for (long long i = 1; i * s.options.dt <= 3.0; ++i) {
    sim.set_tool_poses(s.tool_poses(i));
    sim.step(1.0);
    if (i % 50 == 0) deepest = std::max(deepest, deepest_penetration(m, sim.state()));
  }
  EXPECT_LT(deepest, m.contact.penalty.eps);
}

TEST(ContactScenario, BadInputNamesTheField) {
  auto error_of = [](const std::string& extra) {
    try {
      scene(extra).build_model();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(R"(, "tools": [{"name": "x", "shape": "cone", "contact": {}, "path": {}}])")
                .find("/tools/0/shape"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "contact": {"eps_m": 1e-4, "k_n_m": 10,
                        "mu_pairs": [{"a": "object", "b": "nobody", "mu": 0.1}]})")
                .find("/contact/mu_pairs/0/b"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "tools": [{"name": "g", "shape": "gripper", "axis": [1, 0, 0], "length_m": 0.01,
                        "width_m": 0.01, "thickness_m": 0.01,
                        "contact": {"eps_m": 1e-4, "k_n_m": 10},
                        "path": {"t_s": [0], "position_m": [[0, 0, 0]]}}])")
                .find("/tools/0/path/q"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "tools": [{"name": "s", "shape": "sphere", "radius_m": 0.01,
                        "contact": {"eps_m": 1e-4, "k_n_m": 10},
                        "path": {"t_s": [0, 1], "position_m": [[0, 0, 0]]}}])")
                .find("/tools/0/path/position_m"),
            std::string::npos);
}

TEST(ContactScenario, ObjectsAndToolsAreBounded) {
  std::string tools = R"(, "tools": [)";
  for (int i = 0; i < 17; ++i) {
    tools += std::string(i ? ", " : "") + R"({"name": "s)" + std::to_string(i) +
             R"(", "shape": "sphere", "radius_m": 0.01, "contact": {"eps_m": 1e-4, "k_n_m": 10},
                 "path": {"t_s": [0], "position_m": [[0, 0, 1]]}})";
  }
  tools += "]";
  try {
    scene(tools);
    ADD_FAILURE() << "17 tools accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/tools: expected an array of at most 16 tools"),
              std::string::npos)
        << e.what();
  }
  const std::string big = R"(, "objects": [{"name": "big", "mesh": {"dim": 3, "structure": "lattice",
      "nx": 200, "ny": 200, "nz": 30, "sx_m": 1, "sy_m": 1, "sz_m": 1}, "material": )" +
                          std::string(kStiff) + R"(}])";
  try {
    scene(big);
    ADD_FAILURE() << "a 1.2 M particle scene accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/objects/0/mesh"), std::string::npos) << e.what();
  }
}

TEST(ToolContact, StepWithoutPosesIsRefused) {
  Scenario s = scene(R"(, "tools": [{"name": "s", "shape": "sphere", "radius_m": 0.01,
      "contact": {"eps_m": 1e-4, "k_n_m": 10}, "path": {"t_s": [0], "position_m": [[0, 0, 1]]}}])");
  const Model m = s.build_model();
  s.options = half_bound(m);
  Simulator sim(m, s.options);
  EXPECT_THROW(sim.step(1.0), Error);
  const std::vector<ToolPose> none;
  EXPECT_THROW(sim.set_tool_poses(none), Error);
}

}  // namespace
}  // namespace rheo
