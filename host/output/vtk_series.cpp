#include "host/output/vtk_series.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "sim/edge_kernel.hpp"
#include "sim/error.hpp"

namespace rheo::output {

namespace {

// VTK cell type ids (vtkCellType.h).
constexpr std::uint8_t kVtkLine = 3;
constexpr std::uint8_t kVtkTriangle = 5;
constexpr std::uint8_t kVtkQuad = 9;
constexpr std::uint8_t kVtkTetra = 10;
constexpr std::uint8_t kVtkHexahedron = 12;

using Mat3 = Eigen::Matrix3d;

// One appended array: its XML declaration and its bytes. The raw block in the file is
// the byte count (UInt64, header_type) followed by the bytes.
struct Array {
  std::string type;  // VTK type name (Float32, Int32, UInt8)
  std::string name;
  int components = 1;
  std::string bytes;
};

template <typename T>
Array make_array(const std::string& type, const std::string& name, int components,
                 const std::vector<T>& values) {
  Array a{type, name, components, std::string()};
  a.bytes.resize(values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(a.bytes.data(), values.data(), a.bytes.size());
  return a;
}

Array float_array(const std::string& name, const std::vector<double>& values) {
  std::vector<float> f(values.begin(), values.end());
  return make_array("Float32", name, 1, f);
}

Array vector_array(const std::string& name, const std::vector<Vec3>& v) {
  std::vector<float> out;
  out.reserve(v.size() * 3);
  for (const Vec3& p : v) {
    for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(p[c]));
  }
  return make_array("Float32", name, 3, out);
}

// Row-major 3x3 tensors (ParaView shows 9-component arrays as tensors).
Array tensor_array(const std::string& name, const std::vector<Mat3>& t) {
  std::vector<float> out;
  out.reserve(t.size() * 9);
  for (const Mat3& m : t) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(m(r, c)));
    }
  }
  return make_array("Float32", name, 9, out);
}

// An object's name (the user's text) in an XML attribute: "salt & pepper <dough>" made
// mesh.pvd malformed.
std::string xml_attribute(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

// Text in an XML comment, which may not hold "--".
std::string xml_comment(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '-' && !out.empty() && out.back() == '-') out += ' ';
    out += c;
  }
  return out;
}

void write_declarations(std::ostream& xml, const std::vector<Array>& arrays,
                        std::uint64_t& offset) {
  for (const Array& a : arrays) {
    xml << "        <DataArray type=\"" << a.type << "\"";
    if (!a.name.empty()) xml << " Name=\"" << a.name << "\"";
    if (a.components != 1) xml << " NumberOfComponents=\"" << a.components << "\"";
    xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
    offset += sizeof(std::uint64_t) + a.bytes.size();
  }
}

// Volume (3-D, tetrahedron) or area (2-D, triangle) of a model element at positions x.
double element_measure(const std::vector<Vec3>& x, const int* v, int dim) {
  if (dim == 3) {
    Mat3 m;
    m << x[v[1]] - x[v[0]], x[v[2]] - x[v[0]], x[v[3]] - x[v[0]];
    return std::abs(m.determinant()) / 6.0;
  }
  return 0.5 * (x[v[1]] - x[v[0]]).cross(x[v[2]] - x[v[0]]).norm();
}

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

}  // namespace

// One .vtu file's content: points, cells, and the data arrays.
struct VtkSeriesWriter::Piece {
  std::vector<Vec3> points;
  std::vector<Array> point_data, cell_data;
  Array connectivity, offsets, types;
  int cells = 0;
  std::vector<std::string> comments;  // XML comments (what the file holds and lacks)
};

namespace {

// The tuples of `a` at `index` (a has `count` tuples of equal size).
Array select_tuples(const Array& a, std::size_t count, const std::vector<int>& index) {
  Array out{a.type, a.name, a.components, std::string()};
  if (count == 0) return out;
  const std::size_t size = a.bytes.size() / count;
  out.bytes.reserve(index.size() * size);
  for (int i : index) out.bytes.append(a.bytes, static_cast<std::size_t>(i) * size, size);
  return out;
}

}  // namespace

VtkSeriesWriter::Piece VtkSeriesWriter::object_part(const Piece& all, int object) const {
  // Cells whose first corner belongs to the object (edges and elements never join two
  // objects), and the object's particles renumbered.
  Piece part;
  part.comments = all.comments;
  std::vector<int> point_index, cell_index, renumber(all.points.size(), -1);
  for (std::size_t i = 0; i < all.points.size(); ++i) {
    if (model_.object[i] != object) continue;
    renumber[i] = static_cast<int>(point_index.size());
    point_index.push_back(static_cast<int>(i));
    part.points.push_back(all.points[i]);
  }
  std::vector<std::int32_t> conn, offs;
  std::vector<std::uint8_t> types;
  for (int c = 0; c < static_cast<int>(types_.size()); ++c) {
    const int first = c == 0 ? 0 : offsets_[c - 1];
    if (renumber[connectivity_[first]] < 0) continue;
    cell_index.push_back(c);
    for (int j = first; j < offsets_[c]; ++j) conn.push_back(renumber[connectivity_[j]]);
    offs.push_back(static_cast<std::int32_t>(conn.size()));
    types.push_back(types_[c]);
  }
  part.cells = static_cast<int>(cell_index.size());
  for (const Array& a : all.point_data) {
    part.point_data.push_back(select_tuples(a, all.points.size(), point_index));
  }
  for (const Array& a : all.cell_data) {
    part.cell_data.push_back(select_tuples(a, static_cast<std::size_t>(all.cells), cell_index));
  }
  part.connectivity = make_array("Int32", "connectivity", 1, conn);
  part.offsets = make_array("Int32", "offsets", 1, offs);
  part.types = make_array("UInt8", "types", 1, types);
  return part;
}

VtkSeriesWriter::VtkSeriesWriter(const Model& model, std::string dir, FrameContent content)
    : model_(model), dir_(std::move(dir)), content_(std::move(content)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ + "/vtk", ec);
  if (ec) throw Error(dir_ + "/vtk: cannot create directory: " + ec.message());
  build_cells();
}

// Merges the elements that fill one grid box into a hexahedron (quad), keeps the others
// as tetrahedra (triangles); without elements, falls back to the edges as lines.
void VtkSeriesWriter::build_cells() {
  const int dim = model_.dim;
  const int n = model_.num_particles();
  const int per = dim == 3 ? 4 : 3;  // vertices per element
  std::vector<const int*> elements;
  if (dim == 3) {
    for (const auto& t : model_.tetrahedra) elements.push_back(t.data());
  } else {
    for (const auto& t : model_.triangles) elements.push_back(t.data());
  }
  const std::vector<Vec3>& x0 = model_.x0;
  double size = model_.size;
  if (!(size > 0.0)) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& p : x0) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    size = n > 0 ? (hi - lo).maxCoeff() : 1.0;
  }
  const double tol = 1e-9 * std::max(size, 1e-12);

  // 2-D: the model's plane (normal, for the strain) and its thickness (for the stress).
  if (dim == 2) {
    for (const int* t : elements) {
      const Vec3 c = (x0[t[1]] - x0[t[0]]).cross(x0[t[2]] - x0[t[0]]);
      if (c.norm() > tol * tol) {
        normal_ = c.normalized();
        break;
      }
    }
    const Vec3 across = normal_.cross(Vec3::UnitZ());  // horizontal, in the plane
    if (across.norm() > 0.5) {
      double lo = 1e300, hi = -1e300;
      for (const Vec3& p : x0) lo = std::min(lo, p.dot(across)), hi = std::max(hi, p.dot(across));
      if (hi - lo > tol && model_.top_area > 0.0) depth_ = model_.top_area / (hi - lo);
    }
  }

  auto add_cell = [&](std::uint8_t type, const std::vector<int>& corners,
                      const std::vector<int>& members) {
    for (int c : corners) connectivity_.push_back(c);
    offsets_.push_back(static_cast<std::int32_t>(connectivity_.size()));
    types_.push_back(type);
    element_start_.push_back(static_cast<int>(elements_.size()));
    for (int e : members) elements_.push_back(e);
  };

  if (elements.empty()) {
    truss_fallback_ = true;
    for (const Edge& e : model_.edges) add_cell(kVtkLine, {e.s, e.e}, {});
  } else {
    // The elements of one Kuhn-split box share its main diagonal, their unique longest
    // edge; elements without a unique longest edge stay on their own.
    std::vector<std::pair<int, int>> key(elements.size(), {-1, -1});
    std::map<std::pair<int, int>, std::vector<int>> groups;
    for (std::size_t k = 0; k < elements.size(); ++k) {
      const int* v = elements[k];
      double best = -1.0;
      bool unique = false;
      std::pair<int, int> diagonal;
      for (int a = 0; a < per; ++a) {
        for (int b = a + 1; b < per; ++b) {
          const double l = (x0[v[b]] - x0[v[a]]).norm();
          if (l > best * (1 + 1e-9)) {
            unique = true;
            best = l;
            diagonal = std::minmax(v[a], v[b]);
          } else if (l >= best * (1 - 1e-9)) {
            unique = false;
          }
        }
      }
      if (unique) {
        key[k] = diagonal;
        groups[diagonal].push_back(static_cast<int>(k));
      }
    }
    // The box the group fills, corners in VTK order, or empty.
    auto box_corners = [&](const std::vector<int>& group) -> std::vector<int> {
      const std::size_t corners = dim == 3 ? 8 : 4;
      std::vector<int> verts;
      for (int k : group) verts.insert(verts.end(), elements[k], elements[k] + per);
      std::sort(verts.begin(), verts.end());
      verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
      if (verts.size() != corners) return {};
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (int v : verts) lo = lo.cwiseMin(x0[v]), hi = hi.cwiseMax(x0[v]);
      std::vector<int> axes;
      double box = 1.0;
      for (int a = 0; a < 3; ++a) {
        if (hi[a] - lo[a] > tol) {
          axes.push_back(a);
          box *= hi[a] - lo[a];
        }
      }
      if (static_cast<int>(axes.size()) != dim) return {};
      std::vector<int> by_bits(corners, -1);
      for (int v : verts) {
        int bits = 0;
        for (std::size_t i = 0; i < axes.size(); ++i) {
          const double c = x0[v][axes[i]];
          if (std::abs(c - hi[axes[i]]) <= tol) {
            bits |= 1 << i;
          } else if (std::abs(c - lo[axes[i]]) > tol) {
            return {};
          }
        }
        if (by_bits[bits] >= 0) return {};
        by_bits[bits] = v;
      }
      double filled = 0.0;
      for (int k : group) filled += element_measure(x0, elements[k], dim);
      if (std::abs(filled - box) > 1e-6 * box) return {};
      static constexpr int kHexOrder[8] = {0, 1, 3, 2, 4, 5, 7, 6};
      std::vector<int> ordered;
      for (std::size_t i = 0; i < corners; ++i) ordered.push_back(by_bits[kHexOrder[i]]);
      return ordered;
    };
    std::vector<bool> done(elements.size(), false);
    for (std::size_t k = 0; k < elements.size(); ++k) {
      if (done[k]) continue;
      const std::vector<int> group =
          key[k].first >= 0 ? groups[key[k]] : std::vector<int>{static_cast<int>(k)};
      const std::vector<int> box = group.size() > 1 ? box_corners(group) : std::vector<int>{};
      if (!box.empty()) {
        add_cell(dim == 3 ? kVtkHexahedron : kVtkQuad, box, group);
        (dim == 3 ? hexes_ : quads_)++;
        for (int g : group) done[g] = true;
      } else {
        const int* v = elements[k];
        add_cell(dim == 3 ? kVtkTetra : kVtkTriangle, std::vector<int>(v, v + per),
                 {static_cast<int>(k)});
        (dim == 3 ? tets_ : triangles_)++;
        done[k] = true;
      }
    }
  }
  element_start_.push_back(static_cast<int>(elements_.size()));

  // Each edge's tension goes to the cells that hold both its ends, shared equally.
  const int cells = static_cast<int>(types_.size());
  std::vector<std::vector<int>> cells_of(n);
  for (int c = 0; c < cells; ++c) {
    const int first = c == 0 ? 0 : offsets_[c - 1];
    for (int i = first; i < offsets_[c]; ++i) cells_of[connectivity_[i]].push_back(c);
  }
  std::vector<std::vector<std::pair<int, double>>> per_cell(cells);
  if (!truss_fallback_) {
    for (int k = 0; k < model_.num_edges(); ++k) {
      const Edge& e = model_.edges[k];
      std::vector<int> both;
      std::set_intersection(cells_of[e.s].begin(), cells_of[e.s].end(), cells_of[e.e].begin(),
                            cells_of[e.e].end(), std::back_inserter(both));
      for (int c : both) per_cell[c].emplace_back(k, 1.0 / both.size());
    }
  }
  for (int c = 0; c < cells; ++c) {
    edge_start_.push_back(static_cast<int>(cell_edges_.size()));
    for (const auto& [k, w] : per_cell[c]) {
      cell_edges_.push_back(k);
      edge_weight_.push_back(w);
    }
  }
  edge_start_.push_back(static_cast<int>(cell_edges_.size()));
  stress_ = content_.edge_states && !truss_fallback_ && (dim == 3 || depth_ > 0.0);

  // The plate over the object's top layer (the particles it can touch, else all), wider by
  // 10 % of the object's size on each side so that it shows beside a bulging object.
  std::vector<int> top;
  for (int i = 0; i < n; ++i) {
    if (model_.flags[i] == kPlate) top.push_back(i);
  }
  if (top.empty()) {
    for (int i = 0; i < n; ++i) top.push_back(i);
  }
  if (top.empty() || !content_.plate) return;
  const double margin = 0.1 * size;
  if (dim == 3) {
    double xl = 1e300, xh = -1e300, yl = 1e300, yh = -1e300;
    for (int i : top) {
      xl = std::min(xl, x0[i].x()), xh = std::max(xh, x0[i].x());
      yl = std::min(yl, x0[i].y()), yh = std::max(yh, x0[i].y());
    }
    xl -= margin, xh += margin, yl -= margin, yh += margin;
    plate_corners_ = {Vec3(xl, yl, 0), Vec3(xh, yl, 0), Vec3(xh, yh, 0), Vec3(xl, yh, 0)};
  } else {
    Vec3 across = normal_.cross(Vec3::UnitZ());
    across = across.norm() > 0.5 ? across.normalized() : Vec3::UnitX();
    int lo = top[0], hi = top[0];
    for (int i : top) {
      if (x0[i].dot(across) < x0[lo].dot(across)) lo = i;
      if (x0[i].dot(across) > x0[hi].dot(across)) hi = i;
    }
    plate_corners_ = {x0[lo] - margin * across, x0[hi] + margin * across};
    for (Vec3& p : plate_corners_) p.z() = 0.0;
  }
}

std::string VtkSeriesWriter::object_cells() const {
  if (truss_fallback_) {
    return std::to_string(types_.size()) + " lines (the model has no elements: not shaded)";
  }
  std::vector<std::string> parts;
  auto add = [&](int count, const char* what) {
    if (count > 0) parts.push_back(std::to_string(count) + " " + what);
  };
  add(hexes_, "hexahedra");
  add(tets_, "tetrahedra");
  add(quads_, "quads");
  add(triangles_, "triangles");
  return join(parts);
}

std::vector<std::string> VtkSeriesWriter::absent_arrays() const {
  std::vector<std::string> absent;
  if (!content_.velocities) absent.push_back("velocity_m_s");
  if (!content_.edge_states) absent.push_back("edge_tension_N");
  if (!truss_fallback_ && !stress_) {
    absent.insert(absent.end(), {"stress_Pa", "stress_zz_Pa", "von_mises_stress_Pa"});
  }
  return absent;
}

void VtkSeriesWriter::write_frame(const State& state, const PlateFrame& plate,
                                  const std::vector<ToolFrame>& tools) {
  const Model& model = model_;
  const int n = model.num_particles();
  const int ne = model.num_edges();
  const double t = state.t;
  if (static_cast<int>(state.x.size()) != n) {
    throw Error("VTK frame at t = " + std::to_string(t) + ": state has " +
                std::to_string(state.x.size()) + " positions, the model " + std::to_string(n) +
                " particles");
  }
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%06d.vtu", frames());

  std::vector<Vec3> displacement(n);
  for (int i = 0; i < n; ++i) displacement[i] = state.x[i] - model.x0[i];
  const bool velocities = content_.velocities && static_cast<int>(state.v.size()) == n;
  const bool tensions = content_.edge_states && static_cast<int>(state.d.size()) == ne &&
                        static_cast<int>(state.v.size()) == n;

  // The edges: tension (needs d, m and the velocities) and strain.
  std::vector<double> tension(tensions ? ne : 0), edge_strain(ne);
  for (int k = 0; k < ne; ++k) {
    const Edge& e = model.edges[k];
    edge_strain[k] = ((state.x[e.e] - state.x[e.s]).norm() - e.l0) / e.l0;
    if (tensions) {
      const double m = state.m.empty() ? 0.0 : state.m[k];
      tension[k] = evaluate_edge(model.materials[e.material], state.x[e.s], state.x[e.e],
                                 state.v[e.s], state.v[e.e], state.d[k], e.L, e.l0, m)
                       .tension;
    }
  }
  std::vector<std::string> comments;
  if (!content_.absent_reason.empty() && !absent_arrays().empty()) {
    comments.push_back("rheo: left out: " + join(absent_arrays()) + " (" + content_.absent_reason +
                       ")");
  }
  const std::vector<std::uint8_t> flags(model.flags.begin(), model.flags.end());

  // The plate touches the object when a particle is at or above it (the simulators clamp
  // plate particles to its height); residual deformation only once it has touched and left.
  const double contact_tol = 1e-6 * std::max(model.size, 1e-12);
  bool in_contact = false;
  for (const Vec3& p : state.x) in_contact = in_contact || p.z() >= plate.z_m - contact_tol;
  touched_ = touched_ || plate.force_N > 0.0;
  const bool residual = touched_ && !in_contact;

  // Object.
  Piece object;
  object.points = state.x;
  object.point_data.push_back(vector_array("displacement_m", displacement));
  if (velocities) object.point_data.push_back(vector_array("velocity_m_s", state.v));
  if (residual) object.point_data.push_back(vector_array("residual_deformation_m", displacement));
  object.point_data.push_back(make_array("UInt8", "particle_flag", 1, flags));
  const int cells = static_cast<int>(types_.size());
  object.cells = cells;
  if (truss_fallback_) {
    object.comments.push_back(
        "rheo: the model has no triangles or tetrahedra, so there is no surface to shade: the "
        "object is written as its particles and its edges (line cells)");
    if (tensions) object.cell_data.push_back(float_array("edge_tension_N", tension));
    object.cell_data.push_back(float_array("edge_strain_m_per_m", edge_strain));
  } else {
    std::vector<Mat3> strain(cells), stress(stress_ ? cells : 0);
    std::vector<double> strain_zz(cells), stress_zz(stress_ ? cells : 0),
        von_mises(stress_ ? cells : 0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Mat3 nn = normal_ * normal_.transpose();  // 2-D: keeps F invertible, F n = n
    for (int c = 0; c < cells; ++c) {
      // Least-squares deformation gradient of the corners about their centroids.
      const int first = c == 0 ? 0 : offsets_[c - 1], count = offsets_[c] - first;
      Vec3 X = Vec3::Zero(), x = Vec3::Zero();
      for (int i = first; i < offsets_[c]; ++i) {
        X += model.x0[connectivity_[i]];
        x += state.x[connectivity_[i]];
      }
      X /= count;
      x /= count;
      Mat3 A = nn, B = nn;
      for (int i = first; i < offsets_[c]; ++i) {
        const Vec3 dX = model.x0[connectivity_[i]] - X, dx = state.x[connectivity_[i]] - x;
        A += dx * dX.transpose();
        B += dX * dX.transpose();
      }
      if (std::abs(B.determinant()) > 1e-30 * std::pow(B.trace(), 3)) {
        const Mat3 F = A * B.inverse();
        strain[c] = 0.5 * (F.transpose() * F - Mat3::Identity());
      } else {
        strain[c] = Mat3::Constant(nan);  // degenerate cell: no strain, not zero
      }
      strain_zz[c] = strain[c](2, 2);
      if (!stress_) continue;
      double volume = 0.0;
      for (int j = element_start_[c]; j < element_start_[c + 1]; ++j) {
        const int* v = model.dim == 3 ? model.tetrahedra[elements_[j]].data()
                                      : model.triangles[elements_[j]].data();
        volume += element_measure(state.x, v, model.dim);
      }
      if (model.dim == 2) volume *= depth_;
      Mat3 s = Mat3::Zero();
      for (int j = edge_start_[c]; j < edge_start_[c + 1]; ++j) {
        const Edge& e = model.edges[cell_edges_[j]];
        const Vec3 r = state.x[e.e] - state.x[e.s];
        const double l = r.norm();
        if (l > 0.0) s += edge_weight_[j] * tension[cell_edges_[j]] / l * (r * r.transpose());
      }
      stress[c] = volume > 0.0 ? Mat3(s / volume) : Mat3::Constant(nan);
      stress_zz[c] = stress[c](2, 2);
      const Mat3 dev = stress[c] - stress[c].trace() / 3.0 * Mat3::Identity();
      von_mises[c] = std::sqrt(1.5 * dev.squaredNorm());
    }
    object.cell_data.push_back(tensor_array("strain_m_per_m", strain));
    object.cell_data.push_back(float_array("strain_zz_m_per_m", strain_zz));
    if (stress_) {
      object.cell_data.push_back(tensor_array("stress_Pa", stress));
      object.cell_data.push_back(float_array("stress_zz_Pa", stress_zz));
      object.cell_data.push_back(float_array("von_mises_stress_Pa", von_mises));
    }
  }
  object.connectivity = make_array("Int32", "connectivity", 1, connectivity_);
  object.offsets = make_array("Int32", "offsets", 1, offsets_);
  object.types = make_array("UInt8", "types", 1, types_);
  object.comments.insert(object.comments.end(), comments.begin(), comments.end());
  const int objects = static_cast<int>(model.object_names.size());
  if (objects <= 1) {
    write_piece(std::string("vtk/frame") + suffix, object, t);
  } else {
    for (int k = 0; k < objects; ++k) {
      write_piece("vtk/object" + std::to_string(k) + suffix, object_part(object, k), t);
    }
  }

  // Plate.
  Piece plate_piece;
  for (Vec3 p : plate_corners_) {
    p.z() = plate.z_m;
    plate_piece.points.push_back(p);
  }
  const int plate_cells = plate_corners_.empty() ? 0 : 1;
  plate_piece.cells = plate_cells;
  std::vector<std::int32_t> plate_conn;
  for (int i = 0; i < static_cast<int>(plate_corners_.size()); ++i) plate_conn.push_back(i);
  plate_piece.connectivity = make_array("Int32", "connectivity", 1, plate_conn);
  plate_piece.offsets = make_array(
      "Int32", "offsets", 1,
      std::vector<std::int32_t>(plate_cells, static_cast<std::int32_t>(plate_conn.size())));
  plate_piece.types = make_array(
      "UInt8", "types", 1,
      std::vector<std::uint8_t>(plate_cells, plate_corners_.size() == 4 ? kVtkQuad : kVtkLine));
  plate_piece.cell_data.push_back(
      float_array("plate_force_N", std::vector<double>(plate_cells, plate.force_N)));
  plate_piece.cell_data.push_back(
      float_array("plate_displacement_m", std::vector<double>(plate_cells, plate.displacement_m)));
  if (content_.plate) write_piece(std::string("vtk/plate") + suffix, plate_piece, t);

  // Tools.
  if (tools.size() != model.tools.size()) {
    throw Error("VTK frame at t = " + std::to_string(t) + ": " + std::to_string(tools.size()) +
                " tool frames for the model's " + std::to_string(model.tools.size()) + " tools");
  }
  for (std::size_t k = 0; k < tools.size(); ++k) {
    const ToolFrame& tf = tools[k];
    Piece tp;
    tp.points = tf.surface.points;
    const int cells_k = static_cast<int>(tf.surface.triangles.size());
    tp.cells = cells_k;
    std::vector<std::int32_t> conn, offs;
    for (const auto& tri : tf.surface.triangles) {
      conn.insert(conn.end(), tri.begin(), tri.end());
      offs.push_back(static_cast<std::int32_t>(conn.size()));
    }
    tp.connectivity = make_array("Int32", "connectivity", 1, conn);
    tp.offsets = make_array("Int32", "offsets", 1, offs);
    tp.types = make_array("UInt8", "types", 1, std::vector<std::uint8_t>(cells_k, kVtkTriangle));
    tp.cell_data.push_back(
        vector_array("tool_force_N", std::vector<Vec3>(cells_k, tf.reaction.force)));
    tp.cell_data.push_back(
        vector_array("tool_torque_N_m", std::vector<Vec3>(cells_k, tf.reaction.torque)));
    tp.cell_data.push_back(make_array(
        "Int32", "tool_contacts", 1, std::vector<std::int32_t>(cells_k, tf.reaction.contacts)));
    tp.comments.push_back("rheo: tool \"" + tf.name + "\" (" +
                          tool_shape_name(model.tools[k].shape) +
                          "); tool_force_N and tool_torque_N_m: the reaction the objects exert "
                          "on it (torque about its position)");
    write_piece("vtk/tool" + std::to_string(k) + suffix, tp, t);
  }

  // Edges.
  Piece edges;
  edges.points = state.x;
  edges.point_data.push_back(vector_array("displacement_m", displacement));
  edges.cells = ne;
  if (tensions) edges.cell_data.push_back(float_array("edge_tension_N", tension));
  edges.cell_data.push_back(float_array("edge_strain_m_per_m", edge_strain));
  std::vector<std::int32_t> conn(2 * ne), offs(ne);
  for (int k = 0; k < ne; ++k) {
    conn[2 * k] = model.edges[k].s;
    conn[2 * k + 1] = model.edges[k].e;
    offs[k] = 2 * (k + 1);
  }
  edges.connectivity = make_array("Int32", "connectivity", 1, conn);
  edges.offsets = make_array("Int32", "offsets", 1, offs);
  edges.types = make_array("UInt8", "types", 1, std::vector<std::uint8_t>(ne, kVtkLine));
  edges.comments = comments;
  write_piece(std::string("vtk/edges") + suffix, edges, t);

  times_.push_back(t);
}

void VtkSeriesWriter::write_piece(const std::string& relative, const Piece& piece, double t) const {
  std::vector<float> points;
  points.reserve(piece.points.size() * 3);
  for (const Vec3& p : piece.points) {
    for (int c = 0; c < 3; ++c) points.push_back(static_cast<float>(p[c]));
  }
  const std::vector<Array> point_arrays = {make_array("Float32", "", 3, points)};
  const std::vector<Array> cell_arrays = {piece.connectivity, piece.offsets, piece.types};

  std::ostringstream xml;
  xml << std::setprecision(9);
  const char* byte_order =
      std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  xml << "<?xml version=\"1.0\"?>\n";
  for (const std::string& c : piece.comments) xml << "<!-- " << xml_comment(c) << " -->\n";
  xml << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order
      << "\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <FieldData>\n"
      << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
         "format=\"ascii\">"
      << t << "</DataArray>\n"
      << "    </FieldData>\n"
      << "    <Piece NumberOfPoints=\"" << piece.points.size() << "\" NumberOfCells=\""
      << piece.cells << "\">\n";
  std::uint64_t offset = 0;
  xml << "      <PointData>\n";
  write_declarations(xml, piece.point_data, offset);
  xml << "      </PointData>\n      <CellData>\n";
  write_declarations(xml, piece.cell_data, offset);
  xml << "      </CellData>\n      <Points>\n";
  write_declarations(xml, point_arrays, offset);
  xml << "      </Points>\n      <Cells>\n";
  write_declarations(xml, cell_arrays, offset);
  xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
      << "  <AppendedData encoding=\"raw\">\n   _";

  const std::string path = dir_ + "/" + relative;
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path + ": cannot create file: " + std::strerror(errno));
  out << xml.str();
  for (const auto* arrays : {&piece.point_data, &piece.cell_data, &point_arrays, &cell_arrays}) {
    for (const Array& a : *arrays) {
      const std::uint64_t size = a.bytes.size();
      out.write(reinterpret_cast<const char*>(&size), sizeof size);
      out.write(a.bytes.data(), static_cast<std::streamsize>(a.bytes.size()));
    }
  }
  out << "\n  </AppendedData>\n</VTKFile>\n";
  out.close();
  if (!out) throw Error(path + ": writing failed (disk full?)");
}

std::vector<std::pair<std::string, std::string>> VtkSeriesWriter::mesh_parts() const {
  std::vector<std::pair<std::string, std::string>> parts;
  const int objects = static_cast<int>(model_.object_names.size());
  if (objects <= 1) {
    parts.push_back({objects == 1 ? model_.object_names[0] : "object", "frame"});
  } else {
    for (int k = 0; k < objects; ++k) parts.push_back({model_.object_names[k], "object" + std::to_string(k)});
  }
  if (content_.plate) parts.push_back({"plate", "plate"});
  for (std::size_t k = 0; k < model_.tools.size(); ++k) {
    parts.push_back({model_.tools[k].name, "tool" + std::to_string(k)});
  }
  return parts;
}

void VtkSeriesWriter::close() {
  // mesh.pvd: the object and the plate as parts 0 and 1 of each time step (ParaView shows
  // them as two blocks); edges.pvd: the edge lattice on its own.
  auto write_pvd = [&](const std::string& path,
                       const std::vector<std::pair<std::string, std::string>>& parts) {
    std::ofstream out(path);
    if (!out) throw Error(path + ": cannot create file: " + std::strerror(errno));
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
    char time[64], file[32];
    for (std::size_t f = 0; f < times_.size(); ++f) {
      std::snprintf(time, sizeof time, "%.9g", times_[f]);
      for (std::size_t p = 0; p < parts.size(); ++p) {
        std::snprintf(file, sizeof file, "_%06zu.vtu", f);
        out << "    <DataSet timestep=\"" << time << "\" part=\"" << p << "\" name=\""
            << xml_attribute(parts[p].first) << "\" file=\"vtk/" << xml_attribute(parts[p].second)
            << file << "\"/>\n";
      }
    }
    out << "  </Collection>\n</VTKFile>\n";
    out.close();
    if (!out) throw Error(path + ": writing failed (disk full?)");
  };
  write_pvd(pvd_path(), mesh_parts());
  write_pvd(edges_pvd_path(), {{"edges", "edges"}});
}

}  // namespace rheo::output
