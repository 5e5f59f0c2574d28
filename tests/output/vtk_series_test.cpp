// The VTK series writer: which cells the object becomes (hexahedra from 3-D blocks of either
// structure, quads from 2-D blocks, tetrahedra that fill no box, lines for a model without
// elements), the fields and their absence, the plate part and the failure message. Files are
// read back by a small parser of the appended-raw layout the writer uses.
#include "host/output/vtk_series.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "sim/error.hpp"
#include "sim/mesh.hpp"

namespace rheo::output {
namespace {

namespace fs = std::filesystem;

struct Vtu {
  std::string text;  // the XML part
  int points = 0, cells = 0;
  std::map<std::string, std::vector<float>> floats;  // Float32 arrays by name ("" = points)
  std::map<std::string, int> components;
  std::vector<std::int32_t> connectivity;
  std::vector<std::uint8_t> types;
  bool has(const std::string& name) const { return floats.count(name) > 0; }
};

Vtu read_vtu(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string file = ss.str();
  const std::size_t marker = file.find("<AppendedData encoding=\"raw\">");
  EXPECT_NE(marker, std::string::npos) << path;
  const std::size_t base = file.find('_', marker) + 1;
  Vtu v;
  v.text = file.substr(0, marker);
  std::smatch m;
  std::regex_search(v.text, m, std::regex("NumberOfPoints=\"(\\d+)\" NumberOfCells=\"(\\d+)\""));
  v.points = std::stoi(m[1]);
  v.cells = std::stoi(m[2]);
  const std::regex array(
      "<DataArray type=\"(\\w+)\"(?: Name=\"(\\w*)\")?(?: NumberOfComponents=\"(\\d+)\")? "
      "format=\"appended\" offset=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(v.text.begin(), v.text.end(), array);
       it != std::sregex_iterator(); ++it) {
    const std::string type = (*it)[1], name = (*it)[2];
    const std::size_t at = base + std::stoull((*it)[4]);
    std::uint64_t size = 0;
    std::memcpy(&size, file.data() + at, sizeof size);
    const char* bytes = file.data() + at + sizeof size;
    if (type == "Float32") {
      v.floats[name].resize(size / 4);
      std::memcpy(v.floats[name].data(), bytes, size);
      v.components[name] = (*it)[3].matched ? std::stoi((*it)[3]) : 1;
    } else if (name == "connectivity") {
      v.connectivity.resize(size / 4);
      std::memcpy(v.connectivity.data(), bytes, size);
    } else if (name == "types") {
      v.types.assign(bytes, bytes + size);
    }
  }
  return v;
}

class VtkSeries : public testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("rheo_vtk_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir() const { return dir_.string(); }
  Vtu frame(const char* part, int index = 0) const {
    char name[64];
    std::snprintf(name, sizeof name, "/vtk/%s_%06d.vtu", part, index);
    return read_vtu(dir() + name);
  }
  // Writes one frame of `model` at rest with the plate on its top.
  void write_rest(const Model& model, FrameContent content = {}) {
    VtkSeriesWriter w(model, dir(), std::move(content));
    w.write_frame(initial_state(model), {model.height, 0.0, 0.0});
    w.close();
    cells_ = w.object_cells();
  }

  fs::path dir_;
  std::string cells_;
};

std::vector<int> all(int n, int value) { return std::vector<int>(n, value); }
std::vector<int> as_ints(const std::vector<std::uint8_t>& t) { return {t.begin(), t.end()}; }

TEST_F(VtkSeries, Lattice5x5x5IsWrittenAs64HexahedraInVtkCornerOrder) {
  const Model model = make_block(BlockSpec{});
  write_rest(model);
  EXPECT_EQ(cells_, "64 hexahedra");
  const Vtu v = frame("frame");
  EXPECT_EQ(v.points, 125);
  ASSERT_EQ(v.cells, 64);
  EXPECT_EQ(as_ints(v.types), all(64, 12));
  // First cube: (0,0,0) (1,0,0) (1,1,0) (0,1,0), then the same one layer up.
  const int expected[8] = {0, 1, 6, 5, 25, 26, 31, 30};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(v.connectivity[i], expected[i]) << i;
  for (const char* name : {"displacement_m", "velocity_m_s", "strain_m_per_m", "strain_zz_m_per_m",
                           "stress_Pa", "stress_zz_Pa", "von_mises_stress_Pa"}) {
    EXPECT_TRUE(v.has(name)) << name;
  }
  EXPECT_EQ(v.components.at("strain_m_per_m"), 9);
  // At rest the strain is zero (a value, not a placeholder).
  for (float e : v.floats.at("strain_m_per_m")) EXPECT_NEAR(e, 0.0f, 1e-6f);

  const Vtu edges = frame("edges");
  EXPECT_EQ(edges.cells, model.num_edges());
  EXPECT_EQ(as_ints(edges.types), all(model.num_edges(), 3));
  EXPECT_TRUE(edges.has("edge_tension_N"));
  EXPECT_TRUE(edges.has("edge_strain_m_per_m"));
}

TEST_F(VtkSeries, TrussBlockAlsoGivesHexahedra) {
  BlockSpec spec;
  spec.structure = Structure::kTruss;
  spec.nx = 4;
  write_rest(make_block(spec));
  EXPECT_EQ(cells_, "48 hexahedra");
  EXPECT_EQ(as_ints(frame("frame").types), all(48, 12));
}

TEST_F(VtkSeries, TwoDimensionalBlocksGiveQuadsOfEitherStructure) {
  for (Structure s : {Structure::kLattice, Structure::kTruss}) {
    BlockSpec spec;
    spec.dim = 2;
    spec.nx = 5;
    spec.nz = 3;
    spec.structure = s;
    write_rest(make_block(spec));
    EXPECT_EQ(cells_, "8 quads");
    const Vtu v = frame("frame");
    EXPECT_EQ(as_ints(v.types), all(8, 9));
    EXPECT_TRUE(v.has("stress_zz_Pa"));  // depth = top_area / width
    const Vtu plate = frame("plate");
    EXPECT_EQ(as_ints(plate.types), all(1, 3));  // a line over the 2-D object
    fs::remove_all(dir_);
  }
}

TEST_F(VtkSeries, ATetrahedronThatFillsNoBoxStaysATetrahedron) {
  Model m;
  m.x0 = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.mass.assign(4, 1.0);
  m.flags = {kFixed, kFree, kFree, kPlate};
  m.materials.push_back(EdgeMaterial{1.0, 1.0, 1.0});
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      const double l = (m.x0[b] - m.x0[a]).norm();
      m.edges.push_back({a, b, l, l, 0});
    }
  }
  m.tetrahedra = {{0, 1, 2, 3}};
  m.size = m.height = 1.0;
  write_rest(m);
  EXPECT_EQ(cells_, "1 tetrahedra");
  EXPECT_EQ(as_ints(frame("frame").types), all(1, 10));

  // Without elements it is a general truss: particles and edges, said in the file.
  m.tetrahedra.clear();
  fs::remove_all(dir_);
  write_rest(m);
  const Vtu v = frame("frame");
  EXPECT_EQ(as_ints(v.types), all(6, 3));
  EXPECT_NE(v.text.find("no surface to shade"), std::string::npos);
  EXPECT_TRUE(v.has("edge_tension_N"));
  EXPECT_FALSE(v.has("stress_Pa"));
}

TEST_F(VtkSeries, StatesWithoutEdgeStatesOrVelocitiesLeaveThoseArraysOut) {
  const Model model = make_block(BlockSpec{});
  FrameContent content;
  content.velocities = false;
  content.edge_states = false;
  content.absent_reason = "not read back";
  VtkSeriesWriter w(model, dir(), content);
  EXPECT_EQ(w.absent_arrays(),
            (std::vector<std::string>{"velocity_m_s", "edge_tension_N", "stress_Pa", "stress_zz_Pa",
                                      "von_mises_stress_Pa"}));
  w.write_frame(initial_state(model), {model.height, 0.0, 0.0});
  const Vtu v = frame("frame");
  for (const char* name : {"velocity_m_s", "stress_Pa", "stress_zz_Pa", "von_mises_stress_Pa"}) {
    EXPECT_FALSE(v.has(name)) << name;
  }
  EXPECT_TRUE(v.has("displacement_m"));
  EXPECT_TRUE(v.has("strain_zz_m_per_m"));
  EXPECT_NE(v.text.find("not read back"), std::string::npos);
  EXPECT_FALSE(frame("edges").has("edge_tension_N"));
}

// An affine vertical compression at a constant rate: every cell has the same Green strain,
// every edge with a vertical extent is compressed, and the cells' stresses times their
// volumes add up to the virial of all edges (each edge's share sums to one).
TEST_F(VtkSeries, UniformCompressionGivesUniformStrainAndCompressiveStress) {
  BlockSpec spec;
  spec.material.k1 = 2e4;
  spec.material.c1 = 2e3;
  spec.material.c2 = 2e5;
  const Model model = make_block(spec);
  State s = initial_state(model);
  const double squeeze = 0.9, rate = -0.5;  // z -> 0.9 z, dz/dt = rate * z
  double virial_zz = 0.0;
  for (int i = 0; i < model.num_particles(); ++i) {
    s.x[i].z() *= squeeze;
    s.v[i] = Vec3(0, 0, rate * s.x[i].z());
  }
  for (int k = 0; k < model.num_edges(); ++k) {
    const Edge& e = model.edges[k];
    const EdgeEval<double> eval = evaluate_edge(model.materials[0], s.x[e.s], s.x[e.e], s.v[e.s],
                                                s.v[e.e], s.d[k], e.L, e.l0, 0.0);
    const Vec3 r = s.x[e.e] - s.x[e.s];
    virial_zz += eval.tension * r.z() * r.z() / r.norm();
  }
  VtkSeriesWriter w(model, dir());
  w.write_frame(s, {model.height * squeeze, 0.0, 1.0});
  const Vtu v = frame("frame");
  const double cell_volume = 0.02 * 0.02 * (0.0125 / 4) * squeeze;
  double sum = 0.0;
  for (int c = 0; c < 64; ++c) {
    EXPECT_NEAR(v.floats.at("strain_zz_m_per_m")[c], 0.5 * (squeeze * squeeze - 1.0), 1e-6);
    EXPECT_LT(v.floats.at("stress_zz_Pa")[c], 0.0f);
    sum += v.floats.at("stress_zz_Pa")[c] * cell_volume;
  }
  EXPECT_LT(virial_zz, 0.0);
  EXPECT_NEAR(sum, virial_zz, 1e-5 * std::abs(virial_zz));
}

TEST_F(VtkSeries, ResidualDeformationOnlyAfterThePlateTouchedAndLeft) {
  const Model model = make_block(BlockSpec{});
  State s = initial_state(model);
  VtkSeriesWriter w(model, dir());
  w.write_frame(s, {model.height + 0.001, -0.001, 0.0});  // before contact
  for (Vec3& x : s.x) x.z() *= 0.95;
  w.write_frame(s, {model.height * 0.95, 0.05 * model.height, 2.0});  // under the plate
  w.write_frame(s, {model.height + 0.001, -0.001, 0.0});              // released
  w.close();
  EXPECT_FALSE(frame("frame", 0).has("residual_deformation_m"));
  EXPECT_FALSE(frame("frame", 1).has("residual_deformation_m"));
  const Vtu released = frame("frame", 2);
  ASSERT_TRUE(released.has("residual_deformation_m"));
  EXPECT_EQ(released.floats.at("residual_deformation_m"), released.floats.at("displacement_m"));

  const Vtu plate = frame("plate", 1);
  ASSERT_EQ(plate.points, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_FLOAT_EQ(plate.floats.at("")[3 * i + 2], static_cast<float>(model.height * 0.95));
  }
  EXPECT_FLOAT_EQ(plate.floats.at("plate_force_N")[0], 2.0f);

  std::ifstream pvd(dir() + "/mesh.pvd");
  std::stringstream text;
  text << pvd.rdbuf();
  EXPECT_NE(text.str().find("part=\"1\" name=\"plate\" file=\"vtk/plate_000002.vtu\""),
            std::string::npos)
      << text.str();
  EXPECT_TRUE(fs::exists(dir() + "/edges.pvd"));
}

TEST_F(VtkSeries, AFileThatCannotBeWrittenIsNamed) {
  const Model model = make_block(BlockSpec{});
  VtkSeriesWriter w(model, dir());
  fs::create_directories(dir() + "/vtk/frame_000000.vtu");  // a directory in the way
  try {
    w.write_frame(initial_state(model), {model.height, 0.0, 0.0});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vtk/frame_000000.vtu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rheo::output
