// The bit-true volume element (hls::volume_element) and the element pass of hls::core_step:
// forces against the double formula on random tetrahedra and on random triangles of 2-D
// models (the area's formula; no force on the virtual vertex), no force at rest, saturation,
// the host's element schedule (two rows of one lane per element, ends in distinct banks,
// one vertex order for every lane count), schedule conflicts, and 3-D and 2-D blocks with
// volume (area) preservation against the double reference and across lane counts.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "hls/edge_element.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "sim/element_measure.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::driver {
namespace {

using Fmt = hls::HardwareFormat;

std::int64_t xw(double lu) { return std::llround(std::ldexp(lu, Fmt::kFracX)); }
double fw(std::int64_t w) { return std::ldexp(double(w), -Fmt::kFracF); }
std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// A tetrahedron (or, dim 2, a triangle: p[0..2] in the x-z plane) in length units: the
// element's words, the rest volume (area), c and Y as the host encodes them
// (encode_element), with kv Lu^2 / Fu (kv Lu / Fu) = kv_folded.
struct Tet {
  Eigen::Vector3d p[4];
};

hls::VolumeIn volume_in(const Tet& now, const Tet& rest, double kv_folded, int dim = 3) {
  hls::VolumeIn in;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) in.x[k][i] = xw(now.p[k][i]);
  const ElementWords w = encode_element(dim, rest.p, kv_folded, FormatDesc{}, "element");
  in.v0 = w.v0;
  in.c = w.c;
  in.y = w.y;
  return in;
}

// The reference's forces (Simulator::add_volume_forces) in the same units; f[3] = 0 for a
// triangle.
void reference_forces(const Tet& now, const Tet& rest, double kv_folded, Eigen::Vector3d f[4],
                      int dim = 3) {
  Eigen::Vector3d grad[4];
  const double v = signed_measure<double>(dim, now.p, grad),
               v0 = signed_measure<double>(dim, rest.p, nullptr);
  const double p = -kv_folded * (v - v0) / std::fabs(v0);
  for (int k = 0; k < dim + 1; ++k) f[k] = p * grad[k];
  if (dim == 2) f[3].setZero();
}

Tet random_tet(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.05, 3.0), pos(-10.0, 10.0);
  Tet t;
  const double s = size(rng);
  const Eigen::Vector3d c{pos(rng), pos(rng), pos(rng)};
  // A regular-ish element, jittered, so that it is never nearly flat.
  const Eigen::Vector3d base[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Eigen::Matrix3d rot =
      Eigen::Quaterniond(Eigen::Vector4d{u(rng), u(rng), u(rng), u(rng)}.normalized())
          .toRotationMatrix();
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d jitter{0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)};
    t.p[k] = c + s * (rot * (base[k] + jitter));
  }
  if (u(rng) < 0.0) std::swap(t.p[1], t.p[2]);  // both orientations
  return t;
}

// A triangle in the x-z plane (at a random y), turned about y, and its in-plane deformation.
Tet random_triangle(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.05, 3.0), pos(-10.0, 10.0);
  Tet t;
  const double s = size(rng), turn = 3.14159265358979 * u(rng), y = pos(rng);
  const Eigen::Vector3d c{pos(rng), y, pos(rng)};
  const double base[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (int k = 0; k < 3; ++k) {
    const double bx = base[k][0] + 0.2 * u(rng), bz = base[k][1] + 0.2 * u(rng);
    t.p[k] = c + s * Eigen::Vector3d(std::cos(turn) * bx - std::sin(turn) * bz, 0.0,
                                     std::sin(turn) * bx + std::cos(turn) * bz);
  }
  t.p[3] = Eigen::Vector3d{pos(rng), pos(rng), pos(rng)};  // not a vertex: never read
  if (u(rng) < 0.0) std::swap(t.p[1], t.p[2]);
  return t;
}

Tet deformed_in_plane(const Tet& t, std::mt19937_64& rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  const double a[2][2] = {{1 + u(rng), u(rng)}, {u(rng), 1 + u(rng)}};
  Tet out = t;
  for (int k = 1; k < 3; ++k) {
    const Eigen::Vector3d e = t.p[k] - t.p[0];
    out.p[k] = t.p[0] + Eigen::Vector3d(a[0][0] * e.x() + a[0][1] * e.z(), 0.0,
                                        a[1][0] * e.x() + a[1][1] * e.z());
  }
  return out;
}

// A deformation of a few per cent: a random affine map near the identity.
Tet deformed(const Tet& t, std::mt19937_64& rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) += u(rng);
  Tet out;
  for (int k = 0; k < 4; ++k) out.p[k] = t.p[0] + a * (t.p[k] - t.p[0]);
  return out;
}

// The forces are within 4e-5 of the element's largest force plus two force LSB of the
// double formula: D, P, the gradients and c are each rounded to 18 bits (2^-17 each);
// V6 has 46 fractional bits and its products 35-bit operands, far below that. Returns the
// worst error relative to the element's largest force over 20,000 random elements of
// dimension dim (2: triangles in the x-z plane, whose virtual vertex gets no force and whose
// forces stay in the plane).
double worst_error_against_the_formula(int dim, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> log_kv(-3.0, 1.0);
  double worst = 0.0;
  for (int n = 0; n < 20000; ++n) {
    const Tet rest = dim == 2 ? random_triangle(rng) : random_tet(rng);
    const Tet now = dim == 2 ? deformed_in_plane(rest, rng, 0.05) : deformed(rest, rng, 0.05);
    const double kv = std::pow(10.0, log_kv(rng));
    const hls::VolumeIn in = volume_in(now, rest, kv, dim);
    EXPECT_EQ(in.y > 0, dim == 2);
    std::uint32_t status = 0;
    const hls::VolumeOut out = hls::volume_element<Fmt>(in, &status);
    EXPECT_EQ(status, 0u);
    Eigen::Vector3d ref[4];
    reference_forces(now, rest, kv, ref, dim);
    double fmax = 0.0, err = 0.0;
    for (int k = 0; k < 4; ++k) fmax = std::max(fmax, ref[k].cwiseAbs().maxCoeff());
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) err = std::max(err, std::fabs(fw(out.f[k][i]) - ref[k][i]));
    if (dim == 2) {
      for (int i = 0; i < 3; ++i) EXPECT_EQ(out.f[3][i], 0) << "the virtual vertex, element " << n;
      for (int k = 0; k < 3; ++k) EXPECT_EQ(out.f[k][1], 0) << "out of the plane, element " << n;
    }
    const double lsb = std::ldexp(1.0, -Fmt::kFracF);
    EXPECT_LE(err, 4e-5 * fmax + 2 * lsb) << "element " << n;
    if (::testing::Test::HasFailure()) return worst;
    if (fmax > 1e5 * lsb) worst = std::max(worst, err / fmax);
  }
  return worst;
}

TEST(VolumeKernel, ForcesFollowTheDoubleFormulaOnRandomTetrahedra) {
  const double worst = worst_error_against_the_formula(3, 71);
  RecordProperty("worst_rel_err", sci(worst));
  EXPECT_GT(worst, 0.0);
}

// A triangle runs as the tetrahedron with d = a + Y y^: the same bound against the area's
// formula.
TEST(VolumeKernel, TriangleForcesFollowTheDoubleAreaFormula) {
  const double worst = worst_error_against_the_formula(2, 72);
  RecordProperty("worst_rel_err", sci(worst));
  EXPECT_GT(worst, 0.0);
}

// At rest the element's force is what its positions' rounding (2^-27 Lu) leaves: far below
// the force of a 1e-5 volume change, which an 18-bit V6 would already miss.
TEST(VolumeKernel, RestElementHasNoForceBeyondItsPositionsRounding) {
  std::mt19937_64 rng(73);
  for (int n = 0; n < 2000; ++n) {
    const Tet rest = random_tet(rng);
    std::uint32_t status = 0;
    const hls::VolumeOut out = hls::volume_element<Fmt>(volume_in(rest, rest, 1.0), &status);
    Eigen::Vector3d ref[4];
    reference_forces(deformed(rest, rng, 1e-5), rest, 1.0, ref);
    double scale = 0.0, fmax = 0.0;
    for (int k = 0; k < 4; ++k) {
      scale = std::max(scale, ref[k].cwiseAbs().maxCoeff());
      for (int i = 0; i < 3; ++i) fmax = std::max(fmax, std::fabs(fw(out.f[k][i])));
    }
    // A 1e-5 deformation gives a force near 1e-5 kv |grad|; rest rounding leaves < 1e-6 kv |grad|.
    EXPECT_LT(fmax, 0.1 * scale + 2 * std::ldexp(1.0, -Fmt::kFracF)) << "element " << n;
  }
}

TEST(VolumeKernel, ASaturatedForceRaisesTheFlag) {
  std::mt19937_64 rng(79);
  const Tet rest = random_tet(rng);
  Tet now = rest;
  now.p[3] = now.p[0] + 0.2 * (now.p[3] - now.p[0]);  // squashed to a fifth
  hls::VolumeIn in = volume_in(now, rest, 1.0);
  in.c.shift = -16;  // c 2^16 times larger than any host would encode for this element
  in.c.mant = (1 << 17) - 1;
  std::uint32_t status = 0;
  const hls::VolumeOut out = hls::volume_element<Fmt>(in, &status);
  EXPECT_TRUE(status & hls::kStatusVolumeSaturated);
  bool at_limit = false;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      at_limit = at_limit || out.f[k][i] == (std::int64_t(1) << 31) - 1 ||
                 out.f[k][i] == -(std::int64_t(1) << 31);
  EXPECT_TRUE(at_limit);
}

// ---- the element schedule ----

Scenario volume_block(int n) {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = n;
  s.block.volume.enabled = true;
  s.block.volume.kv = 2e4;  // Pa, near the material's Voigt modulus
  return s;
}

// The 2-D block (n x n particles in the x-z plane, 40 mm deep) with area preservation.
Scenario area_block(int n) {
  Scenario s = load_scenario("block5");
  s.block.dim = 2;
  s.block.nx = s.block.nz = n;
  s.block.ny = 1;
  s.block.volume.enabled = true;
  s.block.volume.kv = 800.0;  // N/m: the 3-D block's 2e4 Pa times its 40 mm depth
  return s;
}

std::vector<std::array<int, 4>> block_tetrahedra(int n) {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = n;
  s.block.volume.enabled = true;
  s.block.volume.kv = 1e4;
  return s.build_model().tetrahedra;
}

void check_schedule(const std::vector<std::array<int, 4>>& tets, const std::vector<int>& lane_counts) {
  ASSERT_FALSE(tets.empty());
  std::vector<std::array<int, 4>> orders;
  for (int lanes : lane_counts) {
    const ElementSchedule sch = schedule_elements(tets, lanes);
    ASSERT_EQ(sch.slot.size(), tets.size());
    std::vector<unsigned> ends_in_row(std::size_t(sch.rows), 0u);
    std::vector<int> taken(std::size_t(sch.rows) * lanes, -1);
    for (std::size_t k = 0; k < tets.size(); ++k) {
      const std::array<int, 4>& v = sch.vertex[k];
      std::array<int, 4> sorted_v = v, sorted_t = tets[k];
      if (tets[k][3] < 0) {  // a triangle: its second half's end is c
        EXPECT_EQ(v[3], v[2]);
        sorted_v[3] = -1;
      }
      std::sort(sorted_v.begin(), sorted_v.end());
      std::sort(sorted_t.begin(), sorted_t.end());
      EXPECT_EQ(sorted_v, sorted_t) << "a permutation of the element's vertices";
      const int lane = sch.slot[k] % lanes, row = sch.slot[k] / lanes;
      EXPECT_EQ(row % 2, 0);
      EXPECT_EQ(v[0] % lanes, lane);
      EXPECT_EQ(v[2] % lanes, lane);
      for (int half = 0; half < 2; ++half) {
        const int slot = (row + half) * lanes + lane;
        EXPECT_EQ(taken[std::size_t(slot)], -1) << "slot used twice";
        taken[std::size_t(slot)] = int(k);
        const unsigned bank = 1u << (v[2 * half + 1] % lanes);
        EXPECT_EQ(ends_in_row[std::size_t(row + half)] & bank, 0u) << "two ends in one bank";
        ends_in_row[std::size_t(row + half)] |= bank;
      }
    }
    if (lanes == 1) {
      EXPECT_EQ(sch.rows, 2 * int(tets.size()));
      for (std::size_t k = 0; k < tets.size(); ++k) orders.push_back(sch.vertex[k]);
    } else {
      for (std::size_t k = 0; k < tets.size(); ++k) EXPECT_EQ(sch.vertex[k], orders[k]);
      // The lane of an element is its vertex a's bank (one vertex order for every lane
      // count), so the busiest lane sets the rows; end-bank clashes add to it (block4 at 2
      // lanes: 216 rows against the busiest lane's 180, its b and d fixed by that order).
      std::vector<int> per_lane(std::size_t(lanes), 0);
      for (std::size_t k = 0; k < tets.size(); ++k) ++per_lane[std::size_t(sch.vertex[k][0] % lanes)];
      const int busiest = *std::max_element(per_lane.begin(), per_lane.end());
      ::testing::Test::RecordProperty("rows_" + std::to_string(tets.size()) + "_" + std::to_string(lanes),
                     std::to_string(sch.rows) + " (busiest lane " + std::to_string(busiest) + ")");
      EXPECT_LE(sch.rows, int(std::ceil(1.25 * 2.0 * busiest)) + 2)
          << lanes << " lanes";
    }
  }
}

// block4 (4 particles per side) runs at every lane count; block5 has elements whose four
// vertices lie in four banks at 4 lanes (refused below), so it runs at 1 and 2.
TEST(ElementSchedule, TwoRowsOfOneLaneWithEndsInDistinctBanks) {
  check_schedule(block_tetrahedra(4), {1, 2, 4});
  check_schedule(block_tetrahedra(5), {1, 2});
  EXPECT_THROW(schedule_elements(block_tetrahedra(5), 4), Error);
}

std::vector<std::array<int, 4>> block_triangles(int n) {
  std::vector<std::array<int, 4>> out;
  for (const auto& t : area_block(n).build_model().triangles) out.push_back({t[0], t[1], t[2], -1});
  return out;
}

TEST(ElementSchedule, TrianglesTakeTwoRowsOfOneLaneWithEndsInDistinctBanks) {
  check_schedule(block_triangles(4), {1, 2, 4});
  check_schedule(block_triangles(5), {1, 2});
  EXPECT_THROW(schedule_elements(block_triangles(5), 4), Error);
}

TEST(ElementSchedule, AnElementWithoutTwoVerticesInOneBankIsRefusedByName) {
  const std::vector<std::array<int, 4>> tets = {{0, 1, 2, 3}};
  EXPECT_NO_THROW(schedule_elements(tets, 2));
  try {
    schedule_elements(tets, 4);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("volume element 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1 or 2 lanes"), std::string::npos) << e.what();
  }
}

// ---- the element pass of the core ----

// The bit-true core (1 lane) against the double reference over 1,500 steps of the push:
// position error and the volume (area) forces' effect on the positions, relative to the size.
void expect_core_follows_reference(const Scenario& s, double* worst_out, double* effect_out) {
  const Model model = s.build_model();
  CoreImage img = make_core_image(model, initial_state(model), s.options.dt, 1, FormatDesc{},
                                  hls::kThreeElementWithVolume);
  EXPECT_TRUE(img.dropped_features.empty());
  EXPECT_EQ(img.num_elements,
            int(model.dim == 2 ? model.triangles.size() : model.tetrahedra.size()));
  auto mem = std::make_unique<hls::CoreMemory>();
  load_memory(img, *mem);
  Simulator ref(hardware_model(model, nullptr, hls::kThreeElementWithVolume), s.options);
  Simulator without(hardware_model(model), s.options);  // no volume forces
  const double size = img.units.length_m * 8.0;
  double worst = 0.0, effect = 0.0;
  for (long n = 1; n <= 1500; ++n) {
    const double z = s.plate_z(model, n);
    mem->globals.plate_z = to_x_word(z, img, "plate");
    hls::core_step<Fmt, 0, false, false, true>(*mem);
    ref.step(z);
    without.step(z);
    ASSERT_EQ(mem->status, 0u) << "step " << n;
    for (int i = 0; i < img.num_particles; ++i) {
      double e2 = 0.0, v2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double d = from_x_word(mem->particles[i].x[a], img) - ref.state().x[i][a];
        const double dv = ref.state().x[i][a] - without.state().x[i][a];
        e2 += d * d;
        v2 += dv * dv;
      }
      worst = std::max(worst, std::sqrt(e2) / size);
      effect = std::max(effect, std::sqrt(v2) / size);
    }
  }
  *worst_out = worst;
  *effect_out = effect;
}

// The words of the core with 1, 2 and 4 lanes (those the model's elements allow) are equal.
void expect_lane_counts_give_identical_words(const Scenario& s, const std::vector<int>& lane_counts) {
  const Model model = s.build_model();
  std::vector<std::vector<std::int32_t>> forces, states;
  for (int lanes : lane_counts) {
    Device dev(std::make_unique<BitTrueTransport>(lanes, hls::kThreeElementWithVolume));
    const CoreImage img = make_core_image(model, initial_state(model), s.options.dt, lanes,
                                          FormatDesc{}, hls::kThreeElementWithVolume);
    dev.load(img);
    std::vector<std::int32_t> plate;
    for (long n = 1; n <= 300; ++n)
      plate.push_back(std::int32_t(to_x_word(s.plate_z(model, n), img, "plate")));
    forces.push_back(dev.run(plate));
    states.push_back(dev.read_particle_state(0, img.num_particles));
    EXPECT_EQ(dev.read_status(false).flags, 0u) << lanes << " lanes";
  }
  for (std::size_t k = 1; k < forces.size(); ++k) {
    EXPECT_EQ(forces[0], forces[k]) << lane_counts[k] << " lanes";
    EXPECT_EQ(states[0], states[k]) << lane_counts[k] << " lanes";
  }
}


// The error stays below 1e-5 of the size while the volume (area) forces move the particles
// by far more.
void expect_follows_with_effect(const Scenario& s, const std::string& effect_name) {
  double worst = 0.0, effect = 0.0;
  expect_core_follows_reference(s, &worst, &effect);
  ::testing::Test::RecordProperty("max_pos_err_rel", sci(worst));
  ::testing::Test::RecordProperty(effect_name + "_effect_rel", sci(effect));
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(effect, 100.0 * worst) << "the " << effect_name
                                   << " forces change the motion far beyond the error";
}

TEST(VolumeCsim, APushedBlockWithVolumeForcesFollowsTheDoubleReference) {
  expect_follows_with_effect(volume_block(4), "volume");
}

TEST(VolumeCsim, APushed2DBlockWithAreaForcesFollowsTheDoubleReference) {
  expect_follows_with_effect(area_block(5), "area");
}

TEST(VolumeCsim, OneTwoAndFourLanesGiveIdenticalWords) {
  expect_lane_counts_give_identical_words(volume_block(4), {1, 2, 4});
}

// Three vertices always have a pair in one bank at 1 and 2 lanes; at 4 lanes a block nx
// particles wide has such a pair in every triangle when nx is a multiple of 4 (a vertex and
// the one above it, nx further, share a bank), which block 5's are not.
TEST(VolumeCsim, A2DBlockGivesIdenticalWordsAtEveryLaneCountItsTrianglesAllow) {
  expect_lane_counts_give_identical_words(area_block(4), {1, 2, 4});
  expect_lane_counts_give_identical_words(area_block(5), {1, 2});
}

// A second half without its first half in the lane's previous row, and an element on a
// core without the unit, are schedule conflicts (the RTL flags the same, rheo_core).
TEST(VolumeCsim, AMalformedElementIsAScheduleConflict) {
  const Scenario s = volume_block(3);
  const Model model = s.build_model();
  const CoreImage img = make_core_image(model, initial_state(model), s.options.dt, 1,
                                        FormatDesc{}, hls::kThreeElementWithVolume);
  auto mem = std::make_unique<hls::CoreMemory>();
  load_memory(img, *mem);
  hls::core_step<Fmt, 0, false, false, true>(*mem);
  EXPECT_FALSE(mem->status & hls::kStatusScheduleConflict);
  load_memory(img, *mem);
  mem->status = 0;
  hls::core_step<Fmt>(*mem);  // the baseline core
  EXPECT_TRUE(mem->status & hls::kStatusScheduleConflict);
  load_memory(img, *mem);
  mem->status = 0;
  // The last element's first half made a bubble: its second half has no first half.
  mem->edges[(img.edge_rows - 2) * img.lanes].valid = false;
  hls::core_step<Fmt, 0, false, false, true>(*mem);
  EXPECT_TRUE(mem->status & hls::kStatusScheduleConflict);
}

TEST(VolumeCsim, TheCycleFormulaCountsTheElementsRows) {
  const Scenario s = volume_block(3);
  const Model model = s.build_model();
  const CoreImage with = make_core_image(model, initial_state(model), s.options.dt, 1,
                                         FormatDesc{}, hls::kThreeElementWithVolume);
  const CoreImage without = make_core_image(model, initial_state(model), s.options.dt, 1);
  EXPECT_EQ(with.edge_rows, without.edge_rows + 2 * int(model.tetrahedra.size()));
  EXPECT_FALSE(without.dropped_features.empty());
}

}  // namespace
}  // namespace rheo::driver
