#include "sim/element_watch.hpp"

#include <cmath>
#include <cstdio>

#include "sim/element_measure.hpp"
#include "sim/error.hpp"

namespace rheo {

ElementWatch::ElementWatch(const Model& model) : dim_(model.dim) {
  const int nv = element_vertex_count(model);
  const std::size_t count = element_count(model);
  for (std::size_t el = 0; el < count; ++el) {
    std::array<int, 4> v{-1, -1, -1, -1};
    Vec3 p[4];
    for (int k = 0; k < nv; ++k) {
      v[k] = element_vertex(model, el, k);
      p[k] = model.x0[v[k]];
    }
    const double rest = signed_measure<double>(dim_, p, nullptr);
    if (!(rest != 0.0) || !std::isfinite(rest)) continue;
    elements_.push_back(el);
    vertices_.push_back(v);
    rest_.push_back(rest);
  }
}

template <typename Position>
std::string ElementWatch::find(const Position& position, double t) const {
  // The hot part, run every step of the reference: the sign of each element's measure only
  // (6 V, or 2 A in 2-D: the formula of signed_measure without its factor, so the same sign),
  // on the positions in place. The message is built for the first inverted element alone.
  const std::size_t count = rest_.size();
  std::size_t w = 0;
  for (; w < count; ++w) {
    const std::array<int, 4>& v = vertices_[w];
    const auto& a = position(v[0]);
    const auto& b = position(v[1]);
    const auto& c = position(v[2]);
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double now;
    if (dim_ == 2) {
      now = ab[2] * ac[0] - ab[0] * ac[2];
    } else {
      const auto& d = position(v[3]);
      const double ad[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
      now = ab[0] * (ac[1] * ad[2] - ac[2] * ad[1]) + ab[1] * (ac[2] * ad[0] - ac[0] * ad[2]) +
            ab[2] * (ac[0] * ad[1] - ac[1] * ad[0]);
    }
    // Zero counts as inverted: the element has been flattened onto itself.
    if (!(now * rest_[w] > 0.0)) break;
  }
  if (w == count) return "";
  const int nv = dim_ == 2 ? 3 : 4;
  Vec3 p[4];
  for (int k = 0; k < nv; ++k) p[k] = Vec3(position(vertices_[w][k]));
  const double now = signed_measure<double>(dim_, p, nullptr);
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < nv; ++k) centre += p[k] / nv;
  const char* kind = dim_ == 2 ? "triangle" : "tetrahedron";
  const char* measure = dim_ == 2 ? "area" : "volume";
  const char* unit = dim_ == 2 ? "m^2" : "m^3";
  char particles[96];
  if (nv == 3) {
    std::snprintf(particles, sizeof particles, "%d, %d, %d", vertices_[w][0], vertices_[w][1],
                  vertices_[w][2]);
  } else {
    std::snprintf(particles, sizeof particles, "%d, %d, %d, %d", vertices_[w][0],
                  vertices_[w][1], vertices_[w][2], vertices_[w][3]);
  }
  char text[512];
  std::snprintf(text, sizeof text,
                "the mesh collapsed at t = %.6g s: %s %zu (particles %s) near (%.4g, %.4g, "
                "%.4g) m has turned inside out (signed %s %.3g %s, %.3g %s at rest); the "
                "particles have passed through one another and the forces no longer describe "
                "the material (docs/model.md, \"When the mesh collapses\")",
                t, kind, elements_[w], particles, centre.x(), centre.y(), centre.z(), measure,
                now, unit, rest_[w], unit);
  return text;
}

std::string ElementWatch::find_inverted(const std::vector<Vec3>& x, double t) const {
  return find([&x](int i) -> const Vec3& { return x[static_cast<std::size_t>(i)]; }, t);
}

std::string ElementWatch::find_inverted(const double* const x[3], double t) const {
  return find([x](int i) { return Vec3(x[0][i], x[1][i], x[2][i]); }, t);
}

void ElementWatch::check(const std::vector<Vec3>& x, double t) const {
  if (rest_.empty()) return;
  if (std::string what = find_inverted(x, t); !what.empty()) throw Error(what);
}

void ElementWatch::check(const double* const x[3], double t) const {
  if (rest_.empty()) return;
  if (std::string what = find_inverted(x, t); !what.empty()) throw Error(what);
}

}  // namespace rheo
