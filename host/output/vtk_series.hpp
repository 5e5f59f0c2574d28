// VTK time series of a particle model for ParaView: one XML UnstructuredGrid (.vtu) per
// frame, the particles as points and the edges as line cells, plus a .pvd collection that
// gives each frame its time. Binary "appended raw" data keep the files small (an ASCII
// block15 series would be hundreds of MB).
//   point data: velocity [m/s], displacement [m] (x - x0), flags (0 free, 1 fixed, 2 plate)
//   cell data:  tension [N] of each edge (> 0 pulls its ends together)
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sim/model.hpp"

namespace rheo::output {

class VtkSeriesWriter {
 public:
  // Frames go to dir/frames_subdir/frame_NNNNNN.vtu, the collection to dir/pvd_name.
  VtkSeriesWriter(std::string dir, std::string frames_subdir, std::string pvd_name);

  // Writes one frame of `state` (at state.t). Throws rheo::Error if it cannot write.
  void write_frame(const Model& model, const State& state);

  // Writes the .pvd collection listing every frame written so far.
  void close();

  int frames() const { return static_cast<int>(frames_.size()); }
  std::string pvd_path() const { return dir_ + "/" + pvd_name_; }

 private:
  std::string dir_;
  std::string frames_subdir_;
  std::string pvd_name_;
  std::vector<std::pair<double, std::string>> frames_;  // time, path relative to dir_
};

}  // namespace rheo::output
