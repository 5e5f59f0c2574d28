// A collapse is never a result: the watch over a model's mesh elements (triangles in 2-D,
// tetrahedra in 3-D) that every CPU path and `rheo simulate` run on the positions they
// compute. An element whose signed area or volume has left the sign it had at rest has
// turned inside out: the particles have passed through one another, the lattice has
// collapsed there, and no force computed from it describes the material. The watch names
// the first such element, where it is, when, and what the measure is against its rest value.
//
// A model without elements (a chain, a hand-made edge list) has nothing to watch: the watch
// is empty and never fails.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "sim/model.hpp"

namespace rheo {

class ElementWatch {
 public:
  ElementWatch() = default;
  // Signed rest measures of the model's elements at x0. An element that is degenerate at
  // rest (zero measure) is not watched: it has no sign to keep.
  explicit ElementWatch(const Model& model);

  bool empty() const { return rest_.empty(); }

  // The first inverted element's description (see above), or "" when none is. Positions
  // per particle, or one array per component (the fast path's layout); `t` is their time [s].
  std::string find_inverted(const std::vector<Vec3>& x, double t) const;
  std::string find_inverted(const double* const x[3], double t) const;

  // Throw rheo::Error with find_inverted's description when an element is inverted.
  void check(const std::vector<Vec3>& x, double t) const;
  void check(const double* const x[3], double t) const;

 private:
  int dim_ = 3;
  std::vector<std::size_t> elements_;          // watched elements' indices in the model
  std::vector<std::array<int, 4>> vertices_;   // their vertices (3 used in 2-D)
  std::vector<double> rest_;                   // their signed rest measures
  template <typename Position>
  std::string find(const Position& position, double t) const;
};

}  // namespace rheo
