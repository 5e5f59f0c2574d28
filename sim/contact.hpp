// Contact among rheological objects and of an object with itself (seed 000 §5.2): the
// penalty method between a surface vertex and a surface face of another object (or of the
// same object, away from the vertex's neighbourhood): a face is a triangle in 3-D and an
// edge in 2-D. When the vertex's signed distance delta to the face's plane (positive on the
// face's outer side) falls below the threshold eps and the foot of the perpendicular lies
// on the face, a virtual Voigt element pushes the vertex out and the face's corners back
// (weights: the foot's barycentric coordinates, so momentum is kept exactly), with Coulomb
// kinetic friction along the relative velocity, as for tools (sim/tool.hpp). docs/contact.md.
//
// Broad phase: a uniform grid whose cell is the largest face (plus the contact reach); each
// face is entered in the cells its reach-expanded bounding box overlaps, and each surface
// vertex looks only at the faces of its own cell. The work per step is about linear in
// the number of surface particles (bench/contact_bench measures the exponent).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "sim/tool.hpp"

namespace rheo {

struct Model;

// Contact between objects (Model::object): the penalty (eps, k, c) of every pair, and the
// friction coefficient per pair of objects.
struct ObjectContact {
  bool enabled = false;
  PenaltyContact penalty;  // eps, k, c, and mu for pairs without their own
  // Friction per pair: objects x objects, symmetric, row-major (the diagonal: self contact).
  // Empty: penalty.mu for every pair.
  std::vector<double> mu;
  bool self = true;  // an object's surface against itself
  double mu_of(int a, int b, int objects) const {
    return mu.empty() ? penalty.mu : mu[static_cast<std::size_t>(a) * objects + b];
  }
};

class ContactDetector {
 public:
  // Finds the objects' surfaces (faces of one element only) and each vertex's neighbours.
  explicit ContactDetector(const Model& model);

  // Adds the contact forces at positions x and velocities v (step dt: friction cap) to f.
  // Returns the number of vertex-face contacts.
  int add_forces(const Model& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                 double dt, std::vector<Vec3>& f);

  int surface_vertices() const { return static_cast<int>(vertices_.size()); }
  int surface_faces() const { return static_cast<int>(faces_.size()); }
  // Candidate pairs the narrow phase looked at in the last add_forces (the broad phase's work).
  long long candidates() const { return candidates_; }

 private:
  bool neighbours(int a, int b) const;

  int dim_ = 3;
  std::vector<std::array<int, 3>> faces_;  // 3-D: outward (b-a)x(c-a); 2-D: c = -1
  std::vector<int> face_object_;
  std::vector<double> rest_thickness_;     // per face: the object's extent behind it at rest
  std::vector<int> vertices_;              // surface particles
  std::vector<int> neighbour_start_, neighbour_;  // CSR, sorted
  // Scratch of add_forces, kept so that a step allocates nothing: per face its depth and
  // reach box, and the grid's (cell key, face) entries, sorted.
  std::vector<double> depth_;
  std::vector<Eigen::AlignedBox3d> reach_;
  std::vector<std::pair<std::uint64_t, int>> cells_;
  long long candidates_ = 0;
};

}  // namespace rheo
