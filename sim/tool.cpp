#include "sim/tool.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/error.hpp"

namespace rheo {

namespace {

[[noreturn]] void fail(const Tool& tool, int index, const std::string& field,
                       const std::string& expected) {
  std::ostringstream os;
  os << "invalid tool " << index << " (\"" << tool.name << "\", " << tool_shape_name(tool.shape)
     << "): " << field << ": expected " << expected;
  throw Error(os.str());
}

// Any unit vector perpendicular to n.
Vec3 perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(a).normalized();
}

void add_box(ToolSurface& s, const Vec3& centre, const Vec3& a, const Vec3& b, const Vec3& c) {
  // A box with half-axes a, b, c: 8 corners, 12 triangles.
  const int base = static_cast<int>(s.points.size());
  for (int i = 0; i < 8; ++i) {
    s.points.push_back(centre + ((i & 1) ? a : Vec3(-a)) + ((i & 2) ? b : Vec3(-b)) +
                       ((i & 4) ? c : Vec3(-c)));
  }
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) {
    s.triangles.push_back({base + q[0], base + q[1], base + q[2]});
    s.triangles.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

// The gripper's finger j (0: at -q/2 along the axis, facing +axis; 1: the other): the centre
// of its contact face and its face normal.
void finger(const Tool& tool, const ToolPose& pose, int j, Vec3& face, Vec3& n) {
  const Vec3 u = tool.axis.normalized();
  const double side = j == 0 ? -1.0 : 1.0;
  face = pose.position + side * 0.5 * pose.q * u;
  n = -side * u;
}

}  // namespace

Vec3 penalty_force(const PenaltyContact& p, const Vec3& n, double delta, const Vec3& relative,
                   double mass, double dt) {
  const double normal_force = std::max(0.0, p.k * (p.eps - delta) - p.c * n.dot(relative));
  Vec3 f = normal_force * n;
  if (p.mu > 0.0 && normal_force > 0.0) {
    const Vec3 slide = relative - n.dot(relative) * n;
    const double speed = slide.norm();
    if (speed > 0.0) f -= std::min(p.mu * normal_force, mass * speed / dt) / speed * slide;
  }
  return f;
}

const char* tool_shape_name(ToolShape shape) {
  switch (shape) {
    case ToolShape::kPlane: return "plane";
    case ToolShape::kSphere: return "sphere";
    case ToolShape::kCylinder: return "cylinder";
    case ToolShape::kGripper: return "gripper";
  }
  return "?";
}

void validate_tool(const Tool& tool, int index) {
  auto positive = [&](const char* field, double value) {
    if (!std::isfinite(value) || value <= 0.0) fail(tool, index, field, "a finite value > 0");
  };
  auto non_negative = [&](const char* field, double value) {
    if (!std::isfinite(value) || value < 0.0) fail(tool, index, field, "a finite value >= 0");
  };
  if (!tool.axis.allFinite() || !(tool.axis.norm() > 0.0)) {
    fail(tool, index, "axis", "a finite non-zero vector");
  }
  positive("contact eps", tool.contact.eps);
  positive("contact k", tool.contact.k);
  non_negative("contact c", tool.contact.c);
  non_negative("contact mu", tool.contact.mu);
  switch (tool.shape) {
    case ToolShape::kPlane:
      non_negative("display_size", tool.display_size);
      break;
    case ToolShape::kSphere:
      positive("radius", tool.radius);
      break;
    case ToolShape::kCylinder:
      positive("radius", tool.radius);
      positive("length", tool.length);
      break;
    case ToolShape::kGripper: {
      positive("length", tool.length);
      positive("width", tool.width);
      positive("thickness", tool.thickness);
      if (!tool.up.allFinite() || !(tool.up.norm() > 0.0)) {
        fail(tool, index, "up", "a finite non-zero vector");
      }
      const double c = std::abs(tool.up.normalized().dot(tool.axis.normalized()));
      if (c > 1e-6) fail(tool, index, "up", "a direction perpendicular to the axis");
      break;
    }
  }
}

bool tool_particle_contact(const Tool& tool, const ToolPose& before, const ToolPose& now, double dt,
                           const Vec3& x, const Vec3& v, double mass, Vec3& force, Vec3& torque) {
  const PenaltyContact& p = tool.contact;
  const Vec3 centre_velocity = (now.position - before.position) / dt;
  force.setZero();
  torque.setZero();
  // One touching surface: its normal n, signed distance, contact point and velocity there.
  auto touch = [&](const Vec3& n, double delta, const Vec3& point, const Vec3& v_surface) {
    if (!(delta < p.eps)) return false;
    const Vec3 f = penalty_force(p, n, delta, v - v_surface, mass, dt);
    force += f;
    torque += (point - now.position).cross(-f);
    return true;
  };
  switch (tool.shape) {
    case ToolShape::kPlane: {
      const Vec3 n = tool.axis.normalized();
      const double delta = n.dot(x - now.position);
      return touch(n, delta, x - delta * n, centre_velocity);
    }
    case ToolShape::kSphere: {
      const Vec3 r = x - now.position;
      const double dist = r.norm();
      if (!(dist - tool.radius < p.eps)) return false;
      const Vec3 n = dist > 0.0 ? Vec3(r / dist) : tool.axis.normalized();
      return touch(n, dist - tool.radius, now.position + tool.radius * n, centre_velocity);
    }
    case ToolShape::kCylinder: {
      const Vec3 u = tool.axis.normalized();
      const Vec3 r = x - now.position;
      const double along = r.dot(u);
      if (std::abs(along) > 0.5 * tool.length) return false;
      const Vec3 radial = r - along * u;
      const double dist = radial.norm();
      if (!(dist - tool.radius < p.eps)) return false;
      const Vec3 n = dist > 0.0 ? Vec3(radial / dist) : perpendicular(u);
      const Vec3 point = now.position + along * u + tool.radius * n;
      const double spin = (now.q - before.q) / dt;  // [rad/s] about u
      const Vec3 v_surface = centre_velocity + spin * u.cross(point - now.position);
      return touch(n, dist - tool.radius, point, v_surface);
    }
    case ToolShape::kGripper: {
      const Vec3 up = tool.up.normalized();
      const Vec3 across = tool.axis.normalized().cross(up);
      bool any = false;
      for (int j = 0; j < 2; ++j) {
        Vec3 face, n, face_before, n_before;
        finger(tool, now, j, face, n);
        finger(tool, before, j, face_before, n_before);
        const Vec3 r = x - face;
        const double delta = n.dot(r);
        if (delta <= -tool.thickness) continue;  // behind the finger
        if (std::abs(r.dot(up)) > 0.5 * tool.length) continue;
        if (std::abs(r.dot(across)) > 0.5 * tool.width) continue;
        any = touch(n, delta, x - delta * n, (face - face_before) / dt) || any;
      }
      return any;
    }
  }
  return false;
}

ToolSurface tool_surface(const Tool& tool, const ToolPose& pose, double scene_size) {
  ToolSurface s;
  const Vec3 c = pose.position;
  switch (tool.shape) {
    case ToolShape::kPlane: {
      const Vec3 n = tool.axis.normalized();
      const Vec3 a = perpendicular(n), b = n.cross(a);
      const double h = 0.5 * (tool.display_size > 0.0 ? tool.display_size : 1.5 * scene_size);
      s.points = {c - h * a - h * b, c + h * a - h * b, c + h * a + h * b, c - h * a + h * b};
      s.triangles = {{0, 1, 2}, {0, 2, 3}};
      break;
    }
    case ToolShape::kSphere: {
      constexpr int kLat = 12, kLon = 24;
      const double pi = std::acos(-1.0);
      s.points.push_back(c + tool.radius * Vec3::UnitZ());
      for (int i = 1; i < kLat; ++i) {
        const double th = pi * i / kLat;
        for (int j = 0; j < kLon; ++j) {
          const double ph = 2.0 * pi * j / kLon;
          s.points.push_back(c + tool.radius * Vec3(std::sin(th) * std::cos(ph),
                                                    std::sin(th) * std::sin(ph), std::cos(th)));
        }
      }
      s.points.push_back(c - tool.radius * Vec3::UnitZ());
      const int south = static_cast<int>(s.points.size()) - 1;
      auto ring = [&](int i, int j) { return 1 + (i - 1) * kLon + (j % kLon); };
      for (int j = 0; j < kLon; ++j) {
        s.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
        s.triangles.push_back({south, ring(kLat - 1, j + 1), ring(kLat - 1, j)});
        for (int i = 1; i + 1 < kLat; ++i) {
          s.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
          s.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
      }
      break;
    }
    case ToolShape::kCylinder: {
      // Turned by q, so that ParaView shows the roller's rotation.
      constexpr int kSeg = 32;
      const double pi = std::acos(-1.0);
      const Vec3 u = tool.axis.normalized();
      const Vec3 a = perpendicular(u), b = u.cross(a);
      const Vec3 e = 0.5 * tool.length * u;
      for (int j = 0; j < kSeg; ++j) {
        const double ph = 2.0 * pi * j / kSeg + pose.q;
        const Vec3 r = tool.radius * (std::cos(ph) * a + std::sin(ph) * b);
        s.points.push_back(c - e + r);
        s.points.push_back(c + e + r);
      }
      s.points.push_back(c - e);
      s.points.push_back(c + e);
      const int lo = 2 * kSeg, hi = 2 * kSeg + 1;
      for (int j = 0; j < kSeg; ++j) {
        const int p0 = 2 * j, p1 = 2 * ((j + 1) % kSeg);
        s.triangles.push_back({p0, p1, p1 + 1});
        s.triangles.push_back({p0, p1 + 1, p0 + 1});
        s.triangles.push_back({lo, p1, p0});
        s.triangles.push_back({hi, p0 + 1, p1 + 1});
      }
      break;
    }
    case ToolShape::kGripper: {
      const Vec3 up = tool.up.normalized();
      const Vec3 across = tool.axis.normalized().cross(up);
      for (int j = 0; j < 2; ++j) {
        Vec3 face, n;
        finger(tool, pose, j, face, n);
        add_box(s, face - 0.5 * tool.thickness * n, 0.5 * tool.thickness * n,
                0.5 * tool.length * up, 0.5 * tool.width * across);
      }
      break;
    }
  }
  return s;
}

ToolPose ToolPath::at(double time) const {
  if (t.empty()) return ToolPose{};
  if (time <= t.front()) return pose.front();
  if (time >= t.back()) return pose.back();
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  const double w = (time - t[k - 1]) / (t[k] - t[k - 1]);
  ToolPose p;
  p.position = (1.0 - w) * pose[k - 1].position + w * pose[k].position;
  p.q = (1.0 - w) * pose[k - 1].q + w * pose[k].q;
  return p;
}

}  // namespace rheo
