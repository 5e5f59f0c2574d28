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
  const int nv = dim_ == 2 ? 3 : 4;
  for (std::size_t w = 0; w < rest_.size(); ++w) {
    Vec3 p[4];
    for (int k = 0; k < nv; ++k) p[k] = position(vertices_[w][k]);
    const double now = signed_measure<double>(dim_, p, nullptr);
    // Zero counts as inverted: the element has been flattened onto itself.
    if (now * rest_[w] > 0.0) continue;
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
  return "";
}

std::string ElementWatch::find_inverted(const std::vector<Vec3>& x, double t) const {
  return find([&x](int i) { return x[static_cast<std::size_t>(i)]; }, t);
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
