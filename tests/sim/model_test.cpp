#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "sim/error.hpp"
#include "sim/mesh.hpp"
#include "sim/model.hpp"

namespace rheo {
namespace {

Model small_block() {
  BlockSpec spec;
  spec.nx = spec.ny = spec.nz = 3;
  spec.material.k1 = 1e4;
  spec.material.c1 = 10.0;
  spec.material.c2 = 100.0;
  return make_block(spec);
}

// Expects validate() to throw a message containing every fragment.
void expect_rejected(const Model& m, const std::string& where, const std::string& field) {
  try {
    validate(m);
    FAIL() << "validate accepted a model with a bad " << where << " " << field;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(where), std::string::npos) << what;
    EXPECT_NE(what.find(field), std::string::npos) << what;
  }
}

TEST(InitialState, StartsAtRestWithVoigtLengthsAtTheirNaturalLength) {
  const Model m = small_block();
  const State s = initial_state(m);
  ASSERT_EQ(s.x.size(), m.x0.size());
  for (int i = 0; i < m.num_particles(); ++i) {
    EXPECT_EQ(s.x[i], m.x0[i]);
    EXPECT_EQ(s.v[i], Vec3::Zero());
  }
  for (int k = 0; k < m.num_edges(); ++k) {
    EXPECT_EQ(s.d[k], m.edges[k].L);
    EXPECT_EQ(s.m[k], 0.0);
  }
  EXPECT_EQ(s.t, 0.0);
}

TEST(Validate, AcceptsAGeneratedBlock) { EXPECT_NO_THROW(validate(small_block())); }

TEST(Validate, RejectsANonPositiveMassNamingTheParticle) {
  Model m = small_block();
  m.mass[7] = 0.0;
  expect_rejected(m, "particle 7", "mass");
}

TEST(Validate, RejectsANonPositiveLengthNamingTheEdge) {
  Model m = small_block();
  m.edges[3].L = -1.0;
  expect_rejected(m, "edge 3", "L");
}

TEST(Validate, RejectsAnOutOfRangeParticleIndex) {
  Model m = small_block();
  m.edges[5].e = m.num_particles();
  expect_rejected(m, "edge 5", "e");
}

TEST(Validate, RejectsANegativeCoefficientNamingTheMaterial) {
  Model m = small_block();
  m.materials[0].k1 = -2.0;
  expect_rejected(m, "material 0", "k1");
}

TEST(Validate, RejectsANaNCoefficient) {
  Model m = small_block();
  m.materials[0].c1 = std::numeric_limits<double>::quiet_NaN();
  expect_rejected(m, "material 0", "c1");
}

TEST(Validate, RejectsAnEdgeWithoutAnyDamper) {
  Model m = small_block();
  m.materials[0].c1 = 0.0;
  m.materials[0].c2 = 0.0;
  expect_rejected(m, "material 0", "c1 + c2");
}

TEST(Validate, RejectsANonlinearDamperWithF2BelowF1) {
  Model m = small_block();
  m.materials[0].nonlinear = true;
  m.materials[0].f1 = 2.0;
  m.materials[0].f2 = 1.0;
  m.materials[0].c2_min = 1.0;
  expect_rejected(m, "material 0", "f2");
}

TEST(Validate, RejectsAMissingMaterial) {
  Model m = small_block();
  m.edges[0].material = 4;
  expect_rejected(m, "edge 0", "material");
}

TEST(Validate, RejectsABadTetrahedronVertex) {
  Model m = small_block();
  m.tetrahedra[2][1] = -1;
  expect_rejected(m, "tetrahedron 2", "vertex");
}

}  // namespace
}  // namespace rheo
