// A vertex against the opposite edge (2-D, in the x-z plane) or face (3-D) of an element or a
// surface: the geometry both the topology-maintenance forces (simulator.cpp) and the contact
// among objects (contact.cpp) push along.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

namespace rheo {

// Unit normal n of the face (2-D: (e.z, 0, -e.x) / |e| for the edge e = b - a; 3-D:
// (b - a) x (c - a) normalised), the signed distance of the vertex along n and the weights of
// the foot point on the face's corners (they sum to 1 and reproduce the foot point, so
// reaction forces spread by them keep momentum and angular momentum; 2-D: the third is 0).
struct VertexFaceGeometry {
  Eigen::Vector3d n;
  double distance;
  double w[3];
  // The foot lies on the face (every weight >= 0, up to rounding).
  bool foot_on_face() const {
    constexpr double kSlack = 1e-9;
    return w[0] >= -kSlack && w[1] >= -kSlack && w[2] >= -kSlack;
  }
};

inline VertexFaceGeometry vertex_face(int dim, const Eigen::Vector3d& xi,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c) {
  VertexFaceGeometry g;
  if (dim == 2) {
    const Eigen::Vector3d e = b - a;
    const double len2 = e.squaredNorm();
    g.n = Eigen::Vector3d(e.z(), 0.0, -e.x()) / std::sqrt(len2);
    g.distance = g.n.dot(xi - a);
    const double t = (xi - a).dot(e) / len2;
    g.w[0] = 1.0 - t;
    g.w[1] = t;
    g.w[2] = 0.0;
    return g;
  }
  const Eigen::Vector3d nn = (b - a).cross(c - a);
  const double nn2 = nn.squaredNorm();
  g.n = nn / std::sqrt(nn2);
  g.distance = g.n.dot(xi - a);
  const Eigen::Vector3d foot = xi - g.distance * g.n;
  g.w[0] = (b - foot).cross(c - foot).dot(nn) / nn2;
  g.w[1] = (c - foot).cross(a - foot).dot(nn) / nn2;
  g.w[2] = 1.0 - g.w[0] - g.w[1];
  return g;
}

}  // namespace rheo
