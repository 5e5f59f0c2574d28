// VTK time series of a particle model for ParaView (XML UnstructuredGrid .vtu per frame,
// .pvd collections that give each frame its time). Binary "appended raw" data keep the
// files small (an ASCII block15 series would be hundreds of MB). Layout in `dir`:
//
//   mesh.pvd   part 0 "object": vtk/frame_NNNNNN.vtu, part 1 "plate": vtk/plate_NNNNNN.vtu;
//              a scene of several objects (Model::object_names) has one part per object
//              instead (named after it, vtk/object<K>_NNNNNN.vtu), a scene without a plate
//              none for it, and every tool (Model::tools) a part of its own (named after it,
//              vtk/tool<K>_NNNNNN.vtu: its surface as triangles, cell data tool_force_N and
//              tool_torque_N_m, the reaction on it, and tool_contacts).
//   edges.pvd  the edge lattice: vtk/edges_NNNNNN.vtu (line cells)
//
// Opening mesh.pvd shows the object as cells a viewer can shade, and the plate. The object's
// cells come from the model's elements (Model::tetrahedra / triangles): the elements that
// fill one axis-aligned grid box (the 6 Kuhn tetrahedra of a cube, the 2 triangles of a
// square) are merged into one VTK_HEXAHEDRON / VTK_QUAD, the others stay VTK_TETRA /
// VTK_TRIANGLE. A model without elements (a general truss) has no volume to shade: its
// object file holds the particles and the edges as line cells, and says so in an XML
// comment. The edges are in their own series because drawn over the shaded object they
// hide it (block5: 1,036 lines over 64 cubes).
//
// Object, point data (SI units in the names):
//   displacement_m          x - x0, from the rest shape (the mesh as built)
//   velocity_m_s            particle velocity (left out when the state has none)
//   residual_deformation_m  x - x0 in the frames after the plate has touched the object (a
//                           frame with plate force > 0) and left it (no particle at or above
//                           the plate): what the push left behind, plus the sag under the
//                           object's own weight. Left out of frames before the first contact
//                           and under the plate, where x - x0 still holds the elastic part that
//                           springs back.
//   particle_flag           0 free, 1 fixed (floor), 2 touched by the plate
// Object, cell data (volume cells; the truss fallback carries the edge fields instead):
//   strain_m_per_m          Green-Lagrange strain E = (F^T F - I) / 2, 3x3 tensor, F the
//                           least-squares deformation gradient of the cell's corners from
//                           x0 to x (2-D: in the model's plane, the normal kept)
//   strain_zz_m_per_m       its vertical component (< 0 compressed)
//   stress_Pa               virial (Cauchy) stress of the edge tensions in the cell,
//                           (1 / V) sum_e w_e T_e r_e (x) r_e / l_e with V the cell's current
//                           volume (2-D: area x depth, depth = Model::top_area / width) and
//                           w_e = 1 / (number of cells holding both ends of edge e); tension
//                           positive. Edge tensions only (no topology or volume forces).
//   stress_zz_Pa            its vertical component (< 0 compressed)
//   von_mises_stress_Pa     sqrt(3/2 s:s), s the deviator of stress_Pa
//   The stress arrays need the edges' Voigt lengths (State::d, m); a frame from a backend
//   that does not read them back leaves them out (FrameContent::edge_states = false).
// Plate (one VTK_QUAD at the plate height over the object's top, 10 % of the object's
// size wider on each side; a VTK_LINE in 2-D), cell data:
//   plate_force_N           reaction force on the plate (> 0 compression)
//   plate_displacement_m    plate displacement from first contact (> 0 pushed down)
// Edges (VTK_LINE per model edge, same points as the object), point data displacement_m,
// cell data:
//   edge_tension_N          tension of the edge (> 0 pulls its ends together); needs the
//                           Voigt lengths like stress_Pa
//   edge_strain_m_per_m     (l - l0) / l0, l its current, l0 its rest length
// Zeros are never written in place of data a state does not hold: such arrays are absent.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim/model.hpp"

namespace rheo::output {

// What the states given to write_frame hold besides positions.
struct FrameContent {
  bool velocities = true;   // State::v: the particles' velocities
  bool edge_states = true;  // State::d (and m): edge tensions and stresses can be computed
  // Why arrays are absent (e.g. "the core's Voigt lengths are not read back"): written into
  // every file as an XML comment, so the files say it themselves.
  std::string absent_reason;
  bool plate = true;  // the scene has a plate (false: no plate part in mesh.pvd)
};

// A tool in one frame (docs/contact.md): its surface and the reaction on it.
struct ToolFrame {
  std::string name;
  ToolSurface surface;
  ToolReaction reaction;
};

// The plate in one frame.
struct PlateFrame {
  double z_m = 0.0;             // plate height [m]
  double displacement_m = 0.0;  // from first contact, > 0 pushed down
  double force_N = 0.0;         // reaction force, > 0 compression
};

class VtkSeriesWriter {
 public:
  // Builds the object's cells from `model` (copied) and creates dir/vtk. Throws rheo::Error
  // if the directory cannot be created.
  VtkSeriesWriter(const Model& model, std::string dir, FrameContent content = {});

  // Writes one frame (objects, plate, tools, edges) of `state` at state.t. Throws
  // rheo::Error naming the file if it cannot write. `tools`: one per Model::tools, in order.
  void write_frame(const State& state, const PlateFrame& plate,
                   const std::vector<ToolFrame>& tools = {});

  // Writes mesh.pvd and edges.pvd listing every frame written so far.
  void close();

  int frames() const { return static_cast<int>(times_.size()); }
  std::string pvd_path() const { return dir_ + "/mesh.pvd"; }
  std::string edges_pvd_path() const { return dir_ + "/edges.pvd"; }
  // "64 hexahedra", "32 quads", "1036 lines (no elements: not shaded)", ...
  std::string object_cells() const;
  // Arrays that FrameContent (or a 2-D model without a depth) keeps out of every frame.
  std::vector<std::string> absent_arrays() const;

 private:
  struct Piece;
  void build_cells();
  void write_piece(const std::string& relative, const Piece& piece, double t) const;
  // The cells and particles of one object of a multi-object model.
  Piece object_part(const Piece& all, int object) const;
  // The parts of mesh.pvd: (part name, file prefix in vtk/).
  std::vector<std::pair<std::string, std::string>> mesh_parts() const;

  Model model_;
  std::string dir_;
  FrameContent content_;
  bool stress_ = false;         // stress arrays written (edge states and a known volume)
  double depth_ = 0.0;          // 2-D: the out-of-plane thickness [m]
  Vec3 normal_ = Vec3::Zero();  // 2-D: unit normal of the model's plane

  // Object cells (VTK connectivity) and, per cell, its model elements (for its volume) and
  // the edges inside it with their share w_e.
  std::vector<std::int32_t> connectivity_, offsets_;
  std::vector<std::uint8_t> types_;
  std::vector<int> element_start_, elements_;
  std::vector<int> edge_start_, cell_edges_;
  std::vector<double> edge_weight_;
  bool truss_fallback_ = false;
  int hexes_ = 0, tets_ = 0, quads_ = 0, triangles_ = 0;

  // The plate's corners at z = 0 (moved to the plate height per frame).
  std::vector<Vec3> plate_corners_;
  bool touched_ = false;  // the plate has touched the object in some frame

  std::vector<double> times_;
};

}  // namespace rheo::output
