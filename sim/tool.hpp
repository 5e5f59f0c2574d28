// Rigid tools that touch the particles of a rheological object (seed 000 §5.2): a plane, a
// sphere indenter, a rotating cylinder (roller) and a two-finger gripper. A tool is moved by
// its pose, given every step (a scenario's pose history, or a haptic caller); it is never
// moved by the object. Its reaction force and torque are what a force sensor on the tool's
// mount would read.
//
// Contact is the seed's penalty method, per particle: when the signed distance delta of a
// particle to the tool's surface (positive outside the tool) falls below the threshold eps,
// a virtual Voigt element pushes it out along the surface normal n,
//     F_n = max(0, k (eps - delta) - c ddelta/dt),        ddelta/dt = n . (v - v_surface),
// (unilateral: it never pulls), and Coulomb-Amontons kinetic friction acts against the
// tangential relative velocity v_t,
//     F_t = -min(mu F_n, m |v_t| / dt) v_t / |v_t|.
// The cap m |v_t| / dt is the force that stops the particle's sliding within the step: with
// it, explicit integration brings a sliding particle to rest instead of making it chatter
// around zero velocity (the static limit is then mu F_n, the kinetic law's). docs/contact.md.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "sim/edge_kernel.hpp"

#include <Eigen/Core>

namespace rheo {

using Vec3 = Eigen::Vector3d;

enum class ToolShape { kPlane, kSphere, kCylinder, kGripper };
const char* tool_shape_name(ToolShape shape);  // "plane", "sphere", "cylinder", "gripper"

// The penalty contact of one tool (or one pair of objects, contact.hpp).
struct PenaltyContact {
  double eps = 0.0;  // [m] threshold: contact while the signed distance is below it
  double k = 0.0;    // [N/m] virtual spring
  double c = 0.0;    // [N s/m] virtual damper
  double mu = 0.0;   // Coulomb kinetic friction coefficient
};

// Where a tool is at one step. position: the plane's point, the sphere's centre, the
// cylinder's centre (on its axis), the gripper's centre between its fingers. q: the
// cylinder's rotation angle about its axis [rad] (right hand), the gripper's opening
// (distance between the fingers' contact faces) [m]; unused for plane and sphere. A tool's
// velocity is the change of its pose over the step divided by dt.
struct ToolPose {
  Vec3 position = Vec3::Zero();
  double q = 0.0;
};

struct Tool {
  std::string name;
  ToolShape shape = ToolShape::kSphere;
  // Plane: its normal, pointing out of the tool into free space. Cylinder: its axis.
  // Gripper: the closing axis (the fingers sit at position -/+ q/2 axis, facing each other).
  Vec3 axis = Vec3(0.0, 0.0, 1.0);
  // Gripper: the direction along its fingers' length (perpendicular to axis).
  Vec3 up = Vec3(0.0, 0.0, 1.0);
  double radius = 0.0;  // [m] sphere, cylinder
  double length = 0.0;  // [m] cylinder length; gripper finger length (along up)
  double width = 0.0;   // [m] gripper finger width (across axis and up)
  double thickness = 0.0;  // [m] gripper finger thickness: deeper particles are not its
  double display_size = 0.0;  // [m] plane: side of the square drawn in VTK (0: automatic)
  PenaltyContact contact;
};

// The reaction on a tool in one step: force and torque (about the tool's position) the
// particles exert on it, and how many particles touch it.
struct ToolReaction {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  // Particles touching the tool; kContactsNotCounted where the backend does not count them
  // (the fixed-point cores return the force only).
  static constexpr int kContactsNotCounted = -1;
  int contacts = 0;
};

// The penalty force (formula above) on a particle at signed distance delta from a surface
// with unit normal n, moving at `relative` velocity to it; `mass` is what the friction cap
// stops (the particle's, or the reduced mass of two particles). Zero when out of reach.
Vec3 penalty_force(const PenaltyContact& p, const Vec3& n, double delta, const Vec3& relative,
                   double mass, double dt);

// Throws rheo::Error naming the tool and the field when a tool is not usable (a zero axis,
// non-positive radius, negative coefficients, ...).
void validate_tool(const Tool& tool, int index);

// The contact of one particle (position x, velocity v, mass m) with a tool that moved from
// `before` to `now` over the step dt. Returns true on contact; then `force` is the force on
// the particle and `torque` the torque of its reaction on the tool about the tool's position
// (a gripper particle may touch both fingers: both count).
bool tool_particle_contact(const Tool& tool, const ToolPose& before, const ToolPose& now, double dt,
                           const Vec3& x, const Vec3& v, double mass, Vec3& force, Vec3& torque);

// The tool's surface at `pose`, as triangles for drawing (VTK): points and index triples.
// scene_size scales what has no size of its own (the plane's square).
struct ToolSurface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
};
ToolSurface tool_surface(const Tool& tool, const ToolPose& pose, double scene_size);

// A tool's pose history: piecewise-linear in time between knots, constant beyond the ends.
struct ToolPath {
  std::vector<double> t;           // [s], strictly increasing
  std::vector<ToolPose> pose;      // pose at t
  ToolPose at(double time) const;
};

}  // namespace rheo
