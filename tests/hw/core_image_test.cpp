// Host-side conversion of a model to the core's fixed-point image: coefficient encoding,
// range checks with messages naming the culprit, edge schedule and cycle formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"

namespace rheo::driver {
namespace {

// 18-bit mantissa: relative encoding error at most 2^-17.
constexpr double kCoefRel = 1.0 / (1 << 17);

Model two_particle_model() {
  Model m;
  m.x0 = {Vec3(0, 0, 0), Vec3(0.01, 0, 0)};
  m.mass = {1e-3, 1e-3};
  m.flags = {kFixed, kFree};
  EdgeMaterial mat;
  mat.k1 = 100.0;
  mat.c1 = 2.0;
  mat.c2 = 1.0;
  m.materials = {mat};
  m.edges = {Edge{0, 1, 0.01, 0.01, 0}};
  m.height = 0.0;
  return m;
}

TEST(CoreImage, CoefficientsEncodeWithin18BitPrecision) {
  for (double v : {1.0, -0.3, 1e-6, 12345.0, 3.14159e-3}) {
    const hls::Coef c = encode_coef(v, "v", 0);
    EXPECT_LT(std::abs(c.mant), 1 << 17);
    EXPECT_NEAR(decode_coef(c), v, kCoefRel * std::fabs(v)) << v;
  }
  EXPECT_EQ(encode_coef(0.0, "zero", 0).mant, 0);
}

TEST(CoreImage, CoefficientTooLargeIsRefusedWithItsName) {
  try {
    encode_coef(1e12, "material 0: ct", 11);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 0: ct"), std::string::npos) << e.what();
  }
}

TEST(CoreImage, EdgeSlotsHoldEveryEdgeOnceInALaneOwningItsStart) {
  const Model m = two_particle_model();
  for (int lanes : {1, 2}) {
    const CoreImage img = make_core_image(m, initial_state(m), 1e-4, lanes);
    EXPECT_EQ(img.edge_rows, 1);
    ASSERT_EQ(img.edges.size(), std::size_t(lanes));
    ASSERT_EQ(img.edge_slot.size(), 1u);
    const hls::EdgeEntry& e = img.edges[img.edge_slot[0]];
    EXPECT_TRUE(e.valid);
    // Particle i is in bank i % lanes at i / lanes; the slot's lane is the start's bank.
    const int lane = img.edge_slot[0] % lanes;
    const int start = int(e.s_local) * lanes + lane;
    const int end = int(e.e_local) * lanes + int(e.e_bank);
    EXPECT_TRUE((start == 0 && end == 1) || (start == 1 && end == 0)) << lanes;
    int valid = 0;
    for (const auto& slot : img.edges) valid += slot.valid;
    EXPECT_EQ(valid, 1);
    // Rows, drains, particle rows (ceil(2 / lanes)).
    EXPECT_EQ(cycles_per_step_formula(img.edge_rows, img.num_particles, lanes),
              1 + kTemDrainCycles + (2 + lanes - 1) / lanes + kMpmDrainCycles);
  }
}

// Every row: at most one edge per lane (one slot each), end particles in pairwise
// different banks; every edge exactly once; rows = the larger of the most edges a lane
// starts and the most edges a bank ends (the bipartite edge-colouring bound).
TEST(CoreImage, ScheduleRowsHaveDistinctEndBanksAndMeetTheLowerBound) {
  const Model m = load_scenario("block5").build_model();
  const int ne = m.num_edges();
  std::vector<std::pair<int, int>> ends;
  for (const Edge& e : m.edges) ends.push_back({e.s, e.e});
  for (int lanes = 1; lanes <= hls::kMaxLanes; ++lanes) {
    const EdgeSchedule sch = schedule_edges(ends, lanes);
    std::vector<int> owner(std::size_t(sch.rows) * lanes, -1);
    std::vector<long> starts(lanes, 0), ends_in(lanes, 0);
    for (int k = 0; k < ne; ++k) {
      const int t = sch.slot[k];
      ASSERT_GE(t, 0);
      ASSERT_LT(t, sch.rows * lanes);
      ASSERT_EQ(owner[t], -1) << "slot used twice";
      owner[t] = k;
      const auto [start, end] = ends[k];
      EXPECT_EQ(start % lanes, t % lanes);
      ++starts[start % lanes];
      ++ends_in[end % lanes];
    }
    for (int r = 0; r < sch.rows; ++r) {
      std::vector<bool> used(lanes, false);
      for (int j = 0; j < lanes; ++j) {
        const int k = owner[std::size_t(r) * lanes + j];
        if (k < 0) continue;
        const int end = ends[k].second;
        EXPECT_FALSE(used[end % lanes]) << "row " << r << ", lanes " << lanes;
        used[end % lanes] = true;
      }
    }
    const long bound = std::max(*std::max_element(starts.begin(), starts.end()),
                                *std::max_element(ends_in.begin(), ends_in.end()));
    EXPECT_EQ(sch.rows, bound) << lanes;
    // Orientations balance the lanes: within 2 % of E / lanes for block5.
    EXPECT_LE(sch.rows, (ne + lanes - 1) / lanes * 1.02) << lanes;
  }
}

TEST(CoreImage, PositionOutsideTheFixedPointRangeIsRefusedNamingTheParticle) {
  Model m = two_particle_model();
  State s = initial_state(m);
  s.x[1] = Vec3(1.0, 0, 0);  // 100 object sizes away
  try {
    make_core_image(m, s, 1e-4, 1);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle 1"), std::string::npos) << e.what();
  }
}

TEST(CoreImage, FeaturesTheHardwareLacksAreListed) {
  Model m = two_particle_model();
  m.materials[0].nonlinear = true;
  m.topology.enabled = true;
  std::vector<std::string> dropped;
  const Model hw = hardware_model(m, &dropped);
  EXPECT_EQ(dropped.size(), 2u);
  EXPECT_FALSE(hw.materials[0].nonlinear);
  EXPECT_FALSE(hw.topology.enabled);
}

}  // namespace
}  // namespace rheo::driver
