#include "host/output/vtk_series.hpp"

#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "sim/edge_kernel.hpp"
#include "sim/error.hpp"

namespace rheo::output {

namespace {

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

std::vector<float> vectors_as_float(const std::vector<Vec3>& v) {
  std::vector<float> out;
  out.reserve(v.size() * 3);
  for (const Vec3& p : v) {
    for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(p[c]));
  }
  return out;
}

void write_declarations(std::ostream& xml, const std::vector<Array>& arrays, std::size_t first,
                        std::size_t count, std::uint64_t& offset) {
  for (std::size_t i = first; i < first + count; ++i) {
    const Array& a = arrays[i];
    xml << "        <DataArray type=\"" << a.type << "\"";
    if (!a.name.empty()) xml << " Name=\"" << a.name << "\"";
    if (a.components != 1) xml << " NumberOfComponents=\"" << a.components << "\"";
    xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
    offset += sizeof(std::uint64_t) + a.bytes.size();
  }
}

}  // namespace

VtkSeriesWriter::VtkSeriesWriter(std::string dir, std::string frames_subdir, std::string pvd_name)
    : dir_(std::move(dir)),
      frames_subdir_(std::move(frames_subdir)),
      pvd_name_(std::move(pvd_name)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ + "/" + frames_subdir_, ec);
  if (ec) throw Error(dir_ + "/" + frames_subdir_ + ": cannot create directory: " + ec.message());
}

void VtkSeriesWriter::write_frame(const Model& model, const State& state) {
  const int n = model.num_particles();
  const int ne = model.num_edges();

  std::vector<Vec3> displacement(n);
  for (int i = 0; i < n; ++i) displacement[i] = state.x[i] - model.x0[i];
  std::vector<float> tension(ne);
  std::vector<std::int32_t> connectivity(2 * ne), offsets(ne);
  for (int k = 0; k < ne; ++k) {
    const Edge& e = model.edges[k];
    const double m = state.m.empty() ? 0.0 : state.m[k];
    const EdgeEval<double> eval =
        evaluate_edge(model.materials[e.material], state.x[e.s], state.x[e.e], state.v[e.s],
                      state.v[e.e], state.d[k], e.L, e.l0, m);
    tension[k] = static_cast<float>(eval.tension);
    connectivity[2 * k] = e.s;
    connectivity[2 * k + 1] = e.e;
    offsets[k] = 2 * (k + 1);
  }
  constexpr std::uint8_t kVtkLine = 3;
  const std::vector<std::uint8_t> types(ne, kVtkLine);
  const std::vector<std::uint8_t> flags(model.flags.begin(), model.flags.end());

  // Order: point data (3), cell data (1), points (1), cells (3).
  const std::vector<Array> arrays = {
      make_array("Float32", "velocity", 3, vectors_as_float(state.v)),
      make_array("Float32", "displacement", 3, vectors_as_float(displacement)),
      make_array("UInt8", "flags", 1, flags),
      make_array("Float32", "tension", 1, tension),
      make_array("Float32", "", 3, vectors_as_float(state.x)),
      make_array("Int32", "connectivity", 1, connectivity),
      make_array("Int32", "offsets", 1, offsets),
      make_array("UInt8", "types", 1, types),
  };

  std::ostringstream xml;
  xml << std::setprecision(9);
  const char* byte_order =
      std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order
      << "\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <FieldData>\n"
      << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
         "format=\"ascii\">"
      << state.t << "</DataArray>\n"
      << "    </FieldData>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << ne << "\">\n";
  std::uint64_t offset = 0;
  xml << "      <PointData Vectors=\"velocity\">\n";
  write_declarations(xml, arrays, 0, 3, offset);
  xml << "      </PointData>\n      <CellData Scalars=\"tension\">\n";
  write_declarations(xml, arrays, 3, 1, offset);
  xml << "      </CellData>\n      <Points>\n";
  write_declarations(xml, arrays, 4, 1, offset);
  xml << "      </Points>\n      <Cells>\n";
  write_declarations(xml, arrays, 5, 3, offset);
  xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
      << "  <AppendedData encoding=\"raw\">\n   _";

  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.vtu", frames());
  const std::string relative = frames_subdir_ + "/" + name;
  const std::string path = dir_ + "/" + relative;
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path + ": cannot create file: " + std::strerror(errno));
  out << xml.str();
  for (const Array& a : arrays) {
    const std::uint64_t size = a.bytes.size();
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(a.bytes.data(), static_cast<std::streamsize>(a.bytes.size()));
  }
  out << "\n  </AppendedData>\n</VTKFile>\n";
  out.close();
  if (!out) throw Error(path + ": writing failed (disk full?)");
  frames_.emplace_back(state.t, relative);
}

void VtkSeriesWriter::close() {
  const std::string path = pvd_path();
  std::ofstream out(path);
  if (!out) throw Error(path + ": cannot create file: " + std::strerror(errno));
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
  char time[64];
  for (const auto& [t, file] : frames_) {
    std::snprintf(time, sizeof time, "%.9g", t);
    out << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << file << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  out.close();
  if (!out) throw Error(path + ": writing failed (disk full?)");
}

}  // namespace rheo::output
