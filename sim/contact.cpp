#include "sim/contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "sim/face_geometry.hpp"
#include "sim/model.hpp"

namespace rheo {

namespace {

int object_of(const Model& model, int i) { return model.object.empty() ? 0 : model.object[i]; }

// Grid cell key of integer cell coordinates (2^21 cells per axis around the origin).
std::uint64_t cell_key(long ix, long iy, long iz) {
  constexpr long kBias = 1l << 20;
  auto part = [](long c) { return static_cast<std::uint64_t>((c + kBias) & ((1l << 21) - 1)); };
  return (part(ix) << 42) | (part(iy) << 21) | part(iz);
}

}  // namespace

ContactDetector::ContactDetector(const Model& model) : dim_(model.dim) {
  const int n = model.num_particles();
  // Boundary faces: those of exactly one element, oriented away from the element's other
  // vertex.
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 4>>> count;  // sorted face ->
  auto add = [&](std::array<int, 3> face, int opposite) {
    std::array<int, 3> key = face;
    std::sort(key.begin(), key.end());
    auto& entry = count[key];
    ++entry.first;
    entry.second = {face[0], face[1], face[2], opposite};
  };
  if (model.dim == 3) {
    for (const auto& t : model.tetrahedra) {
      add({t[0], t[1], t[2]}, t[3]);
      add({t[0], t[1], t[3]}, t[2]);
      add({t[0], t[2], t[3]}, t[1]);
      add({t[1], t[2], t[3]}, t[0]);
    }
  } else {
    for (const auto& t : model.triangles) {
      add({std::min(t[0], t[1]), std::max(t[0], t[1]), -1}, t[2]);
      add({std::min(t[1], t[2]), std::max(t[1], t[2]), -1}, t[0]);
      add({std::min(t[0], t[2]), std::max(t[0], t[2]), -1}, t[1]);
    }
  }
  std::vector<char> on_surface(n, 0);
  for (const auto& [key, entry] : count) {
    if (entry.first != 1) continue;
    std::array<int, 3> f = {entry.second[0], entry.second[1], entry.second[2]};
    const Vec3& o = model.x0[entry.second[3]];
    const VertexFaceGeometry g =
        vertex_face(model.dim, o, model.x0[f[0]], model.x0[f[1]],
                      f[2] >= 0 ? model.x0[f[2]] : Vec3(Vec3::Zero()));
    // The element's own vertex must lie inside: on the negative side.
    if (g.distance > 0.0) std::swap(f[0], f[1]);
    faces_.push_back(f);
    face_object_.push_back(object_of(model, f[0]));
    for (int v : f) {
      if (v >= 0) on_surface[v] = 1;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (on_surface[i]) vertices_.push_back(i);
  }
  // Each face's thickness at rest: how far its object reaches behind it, along the inward
  // normal from its centre to the next face of the same object. A vertex more than half of
  // it behind the face is nearer the object's other side (or came from there), so the face
  // does not claim it (a thin object would otherwise pull a vertex from its far side).
  const int corners = model.dim == 3 ? 3 : 2;
  auto corner = [&](const std::array<int, 3>& f, int c) { return model.x0[f[c]]; };
  for (std::size_t k = 0; k < faces_.size(); ++k) {
    Vec3 centre = Vec3::Zero();
    for (int c = 0; c < corners; ++c) centre += corner(faces_[k], c) / corners;
    const Vec3 nk = vertex_face(model.dim, centre, corner(faces_[k], 0), corner(faces_[k], 1),
                                  corners == 3 ? corner(faces_[k], 2) : Vec3(Vec3::Zero()))
                        .n;
    double thickness = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < faces_.size(); ++j) {
      if (j == k || face_object_[j] != face_object_[k]) continue;
      const Vec3 a = corner(faces_[j], 0), b = corner(faces_[j], 1);
      const Vec3 c = corners == 3 ? corner(faces_[j], 2) : Vec3(Vec3::Zero());
      const VertexFaceGeometry gj = vertex_face(model.dim, centre, a, b, c);
      const double along = gj.n.dot(nk);
      if (std::abs(along) < 1e-12) continue;
      const double t = gj.distance / along;  // centre - t nk lies in face j's plane
      if (!(t > 1e-12 * model.size) || t >= thickness) continue;
      if (vertex_face(model.dim, centre - t * nk, a, b, c).foot_on_face()) thickness = t;
    }
    rest_thickness_.push_back(thickness);
  }
  // Neighbours: joined by an edge or sharing an element.
  std::vector<std::vector<int>> nb(n);
  auto link = [&](int a, int b) {
    nb[a].push_back(b);
    nb[b].push_back(a);
  };
  for (const Edge& e : model.edges) link(e.s, e.e);
  for (const auto& t : model.tetrahedra) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) link(t[a], t[b]);
    }
  }
  for (const auto& t : model.triangles) {
    for (int a = 0; a < 3; ++a) link(t[a], t[(a + 1) % 3]);
  }
  neighbour_start_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) {
    std::sort(nb[i].begin(), nb[i].end());
    nb[i].erase(std::unique(nb[i].begin(), nb[i].end()), nb[i].end());
    neighbour_start_[i + 1] = neighbour_start_[i] + static_cast<int>(nb[i].size());
    neighbour_.insert(neighbour_.end(), nb[i].begin(), nb[i].end());
  }
}

bool ContactDetector::neighbours(int a, int b) const {
  if (a == b) return true;
  const auto first = neighbour_.begin() + neighbour_start_[a];
  const auto last = neighbour_.begin() + neighbour_start_[a + 1];
  return std::binary_search(first, last, b);
}

int ContactDetector::add_forces(const Model& model, const std::vector<Vec3>& x,
                                const std::vector<Vec3>& v, double dt, std::vector<Vec3>& f) {
  candidates_ = 0;
  if (faces_.empty()) return 0;
  const ObjectContact& oc = model.contact;
  const PenaltyContact& pen = oc.penalty;
  const int objects = std::max<int>(1, static_cast<int>(model.object_names.size()));
  const int corners = dim_ == 3 ? 3 : 2;
  // How deep behind a face a vertex may be and still count as touching it: the face's size
  // (deeper, it is closer to another face of that object, or has gone through).
  std::vector<double>& depth = depth_;
  depth.resize(faces_.size());
  // The region where a face can claim a vertex: the prism from eps in front of it to its
  // depth behind it. Cells are as large as the largest face (with eps), and each face is
  // entered in the cells its prism's box overlaps.
  std::vector<Eigen::AlignedBox3d>& reach = reach_;
  reach.resize(faces_.size());
  double cell = 0.0;
  for (std::size_t k = 0; k < faces_.size(); ++k) {
    Eigen::AlignedBox3d box;
    double edge_sum = 0.0;
    for (int c = 0; c < corners; ++c) {
      box.extend(x[faces_[k][c]]);
      edge_sum += (x[faces_[k][c]] - x[faces_[k][(c + 1) % corners]]).norm();
    }
    depth[k] = std::min(0.5 * rest_thickness_[k], std::max(pen.eps, edge_sum / corners));
    cell = std::max(cell, box.sizes().maxCoeff() + 2.0 * pen.eps);
    const Vec3 n = vertex_face(dim_, x[faces_[k][0]], x[faces_[k][0]], x[faces_[k][1]],
                                 corners == 3 ? x[faces_[k][2]] : Vec3(Vec3::Zero()))
                       .n;
    reach[k] = box;
    reach[k].extend(box.min() - depth[k] * n).extend(box.max() - depth[k] * n);
    reach[k].extend(box.min() + pen.eps * n).extend(box.max() + pen.eps * n);
    reach[k].min().array() -= pen.eps;
    reach[k].max().array() += pen.eps;
  }
  if (!(cell > 0.0) || !std::isfinite(cell)) return 0;
  const double inv = 1.0 / cell;
  cells_.clear();
  for (std::size_t k = 0; k < faces_.size(); ++k) {
    const Vec3 lo = reach[k].min() * inv, hi = reach[k].max() * inv;
    for (long ix = std::lround(std::floor(lo.x())); ix <= std::lround(std::floor(hi.x())); ++ix) {
      for (long iy = std::lround(std::floor(lo.y())); iy <= std::lround(std::floor(hi.y())); ++iy) {
        for (long iz = std::lround(std::floor(lo.z())); iz <= std::lround(std::floor(hi.z()));
             ++iz) {
          cells_.push_back({cell_key(ix, iy, iz), static_cast<int>(k)});
        }
      }
    }
  }
  std::sort(cells_.begin(), cells_.end());
  int contacts = 0;
  for (int p : vertices_) {
    const Vec3& xp = x[p];
    const std::uint64_t key = cell_key(std::lround(std::floor(xp.x() * inv)),
                                       std::lround(std::floor(xp.y() * inv)),
                                       std::lround(std::floor(xp.z() * inv)));
    auto it = std::lower_bound(cells_.begin(), cells_.end(), std::make_pair(key, -1));
    const int op = object_of(model, p);
    int best = -1;
    VertexFaceGeometry best_g{};
    for (; it != cells_.end() && it->first == key; ++it) {
      const int k = it->second;
      const auto& face = faces_[k];
      const int of = face_object_[k];
      if (of == op) {
        if (!oc.self) continue;
        bool near = false;
        for (int c = 0; c < corners && !near; ++c) near = neighbours(p, face[c]);
        if (near) continue;
      }
      ++candidates_;
      const VertexFaceGeometry g = vertex_face(dim_, xp, x[face[0]], x[face[1]],
                                           corners == 3 ? x[face[2]] : Vec3(Vec3::Zero()));
      if (!g.foot_on_face() || !(g.distance < pen.eps) || !(g.distance > -depth[k])) continue;
      // The nearest face's surface: the largest signed distance.
      if (best < 0 || g.distance > best_g.distance) {
        best = k;
        best_g = g;
      }
    }
    if (best < 0) continue;
    const auto& face = faces_[best];
    Vec3 v_foot = Vec3::Zero();
    double face_mass = 0.0;
    bool face_fixed = false;
    for (int c = 0; c < corners; ++c) {
      v_foot += best_g.w[c] * v[face[c]];
      face_mass += best_g.w[c] * model.mass[face[c]];
      face_fixed = face_fixed || model.flags[face[c]] == kFixed;
    }
    const double mass_p = model.mass[p];
    const double reduced = model.flags[p] == kFixed ? (face_fixed ? 0.0 : face_mass)
                           : face_fixed            ? mass_p
                                                   : mass_p * face_mass / (mass_p + face_mass);
    PenaltyContact pair = pen;
    pair.mu = oc.mu_of(op, face_object_[best], objects);
    const Vec3 force = penalty_force(pair, best_g.n, best_g.distance, v[p] - v_foot, reduced, dt);
    if (force.isZero(0.0)) continue;
    f[p] += force;
    for (int c = 0; c < corners; ++c) f[face[c]] -= best_g.w[c] * force;
    ++contacts;
  }
  return contacts;
}

}  // namespace rheo
