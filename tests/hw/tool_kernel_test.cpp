// The bit-true tool unit (hls/tool_contact.hpp) computes the reference model's penalty
// contact with Coulomb kinetic friction (sim/tool.hpp): for planes, spheres and turning
// cylinders in moving poses, particles of several masses about their surfaces and mu from 0
// to 1, the fixed-point force on each particle equals the double one within the 18-bit
// operands' resolution, both where the particle slides (F_t = mu F_n) and where friction
// stops it in one step (the cap m |v_t| / dt), and the contact decision is the same except
// within the resolution of its thresholds (the contact distance, a cylinder's end, the
// penalty force's zero). encode_tool refuses what the unit does not compute,
// naming the tool.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hls/tool_contact.hpp"
#include "host/driver/tool_regs.hpp"
#include "sim/error.hpp"

namespace rheo {
namespace {

using Fmt = hls::HardwareFormat;

driver::CoreImage image_with_units(double Lu, double Fu, double dt) {
  driver::CoreImage img;
  img.units = {Lu, Fu, dt};
  return img;
}

struct Counts {
  int compared = 0, contact = 0, near_threshold = 0;
  int sliding = 0, stopped = 0;  // in contact with mu > 0: F_t = mu F_n, or the cap
  double worst = 0.0;  // largest |f - f_ref| / its bound
};

Counts compare(ToolShape shape, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // Every compiler must draw the same samples: the order in which a call's arguments are
  // evaluated is the compiler's choice, a braced list's is left to right.
  const auto gauss3 = [&] { return Vec3{gauss(rng), gauss(rng), gauss(rng)}; };
  const double Lu = 0.0075, Fu = 15.0, dt = 1e-3;
  const driver::CoreImage img = image_with_units(Lu, Fu, dt);
  Counts n;
  for (int trial = 0; trial < 40; ++trial) {
    Tool tool;
    tool.name = "t";
    tool.shape = shape;
    tool.axis = gauss3().normalized();
    tool.radius = 0.005 + 0.02 * unit(rng);
    tool.length = 0.02 + 0.04 * unit(rng);
    tool.contact = {0.0005 + 0.002 * unit(rng), 500 + 5000 * unit(rng),
                    trial % 5 == 0 ? 0.0 : 10 * unit(rng), trial % 4 == 0 ? 0.0 : unit(rng)};
    ToolPose before, now;
    before.position = 0.06 * Vec3{unit(rng), unit(rng), unit(rng)};
    now.position = before.position + 0.004 * dt * gauss3();
    before.q = unit(rng);
    now.q = before.q + 2.0 * dt * gauss(rng);  // the roller turns (its surface drags)
    const hls::ToolRegs regs = driver::encode_tool(tool, 0, before, now, img);
    const double scale = tool.contact.k * tool.contact.eps;
    for (int k = 0; k < 400; ++k) {
      // a particle about the surface: from 2 eps inside to 2 eps beyond the threshold
      const Vec3 dir = gauss3().normalized();
      const double gap = (unit(rng) * 4.0 - 2.0) * tool.contact.eps;
      Vec3 x;
      double along = 0.0;  // the cylinder's axial coordinate (its ends are a threshold too)
      if (shape == ToolShape::kPlane) {
        const Vec3 side = (dir - dir.dot(tool.axis) * tool.axis) * 0.02;
        x = now.position + side + gap * tool.axis;
      } else if (shape == ToolShape::kSphere) {
        x = now.position + (tool.radius + gap) * dir;
      } else {
        const Vec3 radial = (dir - dir.dot(tool.axis) * tool.axis).normalized();
        along = (unit(rng) - 0.5) * 1.2 * tool.length;
        x = now.position + along * tool.axis + (tool.radius + gap) * radial;
      }
      // Slides from a crawl (friction stops them: the cap) to ~1 m/s, masses over a decade.
      const double speed = std::exp(-7.0 * unit(rng)) * 0.5;
      const Vec3 v = speed * gauss3();
      const double mass = 1e-3 * std::exp(2.3 * unit(rng));
      const hls::Coef minv =
          driver::encode_coef(Fu * dt * dt / (mass * Lu), "minv", hls::CoefShifts<Fmt>::kMinv);
      Vec3 f_ref, torque;
      const bool ref_touch =
          tool_particle_contact(tool, before, now, dt, x, v, mass, f_ref, torque);
      std::int64_t xw[3], pw[3];
      for (int a = 0; a < 3; ++a) {
        xw[a] = driver::to_x_word(x[a], img, "x");
        pw[a] = std::llround(std::ldexp(v[a] * dt / Lu, Fmt::kFracP));
      }
      std::uint32_t status = 0;
      const hls::ToolOut out = hls::tool_particle<Fmt>(xw, pw, minv, regs, &status);
      EXPECT_EQ(status, 0u);
      const Vec3 f(driver::from_f_word(out.f[0], img), driver::from_f_word(out.f[1], img),
                   driver::from_f_word(out.f[2], img));
      const bool ref_push = ref_touch && f_ref.norm() > 0.0;
      // The resolution: the unit normal or axis is a Q1.16 operand, so the surface the
      // hardware sees is turned by up to ~2^-16 rad about the tool's position (a distance
      // error of |x - c| 2^-16); every other operand has 18 bits.
      const double lever = (x - now.position).norm();
      const double distance_resolution =
          lever * std::ldexp(1.0, -15) + tool.contact.eps * std::ldexp(1.0, -14);
      if (ref_push != out.contact) {
        // Only within the resolution of a threshold: the contact distance eps (where the
        // damper's share of the force jumps in, so the force there need not be small), a
        // cylinder's end, or where the penalty force crosses zero (then it is a hair).
        ++n.near_threshold;
        const bool at_eps = std::abs(gap - tool.contact.eps) < distance_resolution;
        const bool at_end = shape == ToolShape::kCylinder &&
                            std::abs(std::abs(along) - 0.5 * tool.length) < distance_resolution;
        if (!at_eps && !at_end) {
          EXPECT_LT(std::max(f_ref.norm(), f.norm()), 1e-4 * scale)
              << tool_shape_name(shape) << " trial " << trial << " particle " << k
              << ": gap / eps = " << gap / tool.contact.eps << ", reference touches "
              << ref_touch << ", f = " << f.transpose() << ", reference " << f_ref.transpose();
        }
        continue;
      }
      ++n.compared;
      n.contact += out.contact;
      // The force's bound follows from the distance resolution above. Friction adds mu
      // times the normal force's error, and the slide's direction and length (18-bit
      // operands of dp, its normal part and the surface's drag) times m / dt^2 where the
      // cap holds.
      const double normal_bound =
          tool.contact.k * lever * std::ldexp(1.0, -15) + 2e-4 * f_ref.norm() + 1e-5 * scale;
      double friction_bound = 0.0;
      if (out.contact && tool.contact.mu > 0.0) {
        Tool frictionless = tool;
        frictionless.contact.mu = 0.0;
        Vec3 fn_ref, unused;
        tool_particle_contact(frictionless, before, now, dt, x, v, mass, fn_ref, unused);
        const Vec3 v_surface_bound = (now.position - before.position) / dt;
        const double slide_scale =
            v.norm() + v_surface_bound.norm() + std::abs(now.q - before.q) / dt * tool.radius;
        friction_bound = tool.contact.mu * normal_bound +
                         mass * slide_scale * std::ldexp(1.0, -14) / dt;
        const double ft = (f_ref - fn_ref).norm();
        (ft > 0.999 * tool.contact.mu * fn_ref.norm() ? n.sliding : n.stopped) += 1;
      }
      const double bound = normal_bound + friction_bound;
      const double err = (f - f_ref).norm() / bound;
      n.worst = std::max(n.worst, err);
      EXPECT_LT(err, 1.0) << tool_shape_name(shape) << " trial " << trial << " particle " << k
                          << ": f = " << f.transpose() << ", reference " << f_ref.transpose();
    }
  }
  return n;
}

TEST(ToolKernel, PlaneSphereAndCylinderForcesEqualTheReferencePenaltyContactWithFriction) {
  for (ToolShape shape : {ToolShape::kPlane, ToolShape::kSphere, ToolShape::kCylinder}) {
    const Counts n = compare(shape, 3 + static_cast<int>(shape));
    std::printf("%s: %d compared, %d in contact (%d sliding, %d stopped by friction), "
                "%d at a threshold, worst |df| / bound = %.2f\n",
                tool_shape_name(shape), n.compared, n.contact, n.sliding, n.stopped,
                n.near_threshold, n.worst);
    EXPECT_GT(n.contact, 3000) << tool_shape_name(shape);
    EXPECT_GT(n.sliding, 300) << tool_shape_name(shape);
    EXPECT_GT(n.stopped, 300) << tool_shape_name(shape);
    EXPECT_GT(n.compared - n.contact, 3000) << tool_shape_name(shape);
    EXPECT_LT(n.near_threshold, 20) << tool_shape_name(shape);
  }
}

TEST(ToolKernel, EncodeToolRefusesGrippersAndCoefficientsOutOfFormatNamingTheTool) {
  const driver::CoreImage img = image_with_units(0.0075, 15.0, 1e-3);
  Tool tool;
  tool.name = "finger";
  tool.shape = ToolShape::kGripper;
  tool.contact = {0.001, 1000, 1, 0.0};
  const ToolPose pose;
  try {
    driver::encode_tool(tool, 2, pose, pose, img);
    ADD_FAILURE() << "a gripper was encoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tool 2 (\"finger\")"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gripper"), std::string::npos) << e.what();
  }
  tool.shape = ToolShape::kSphere;
  tool.radius = 0.01;
  tool.contact.mu = 0.3;
  EXPECT_NO_THROW(driver::encode_tool(tool, 0, pose, pose, img));  // friction is computed
  tool.contact.mu = 1e20;  // beyond the coefficient format
  try {
    driver::encode_tool(tool, 0, pose, pose, img);
    ADD_FAILURE() << "mu = 1e20 was encoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("contact mu"), std::string::npos) << e.what();
  }
  tool.contact.mu = 0.0;
  tool.contact.k = 1e12;  // k Lu / Fu beyond the coefficient format
  EXPECT_THROW(driver::encode_tool(tool, 0, pose, pose, img), Error);
}

}  // namespace
}  // namespace rheo
