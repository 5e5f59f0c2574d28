// Host-side conversion of a model to the core's fixed-point image: coefficient encoding,
// range checks with messages naming the culprit, gather table layout and cycle formula.
#include <gtest/gtest.h>

#include <cmath>

#include "host/driver/core_image.hpp"
#include "sim/error.hpp"

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

TEST(CoreImage, GatherTableListsEveryIncidenceOncePerLane) {
  const Model m = two_particle_model();
  for (int lanes : {1, 2}) {
    const CoreImage img = make_core_image(m, initial_state(m), 1e-4, lanes);
    // One lane walks both particles; two lanes take one particle each.
    const int rows = lanes == 1 ? 2 : 1;
    EXPECT_EQ(img.gather_rows, rows);
    ASSERT_EQ(img.gather.size(), std::size_t(rows * lanes));
    int incidences = 0, lasts = 0;
    for (const auto& g : img.gather) {
      incidences += g.valid;
      lasts += g.last;
    }
    EXPECT_EQ(incidences, 2) << lanes;
    EXPECT_EQ(lasts, 2) << lanes;
    EXPECT_EQ(cycles_per_step_formula(img.num_edges, img.gather_rows, lanes),
              1 + kTemDrainCycles + rows + kMpmDrainCycles);
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
