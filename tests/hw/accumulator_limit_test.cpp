// The core's wide sums at their limits, on the bit-true model and the RTL alike.
//
// Force sums: each particle has two ForceAccW-bit accumulators (forces as start and as end
// of an edge) that do not saturate; they rely on the host's limit of 255 edges per particle
// (make_core_image). 255 edge forces of at most 2^(W-1) each sum to at most 255 * 2^31 <
// 2^39, inside the 40-bit accumulator, so a sum cannot wrap. The test puts a particle at
// that limit with every edge force saturated in the same direction: the exact sum lies above
// 2^38, so an accumulator one bit narrower would wrap to the wrong sign and the particle
// would move away from its edges. The sum must saturate to the right sign once, when it is
// narrowed for the MPM (the MPM flag), the particle must move toward its edges, and the RTL
// must equal the bit-true model bit for bit. One more edge is refused by the host.
//
// Maxwell arms' force: a four-arm TEM sums the arms' forces exactly and adds them into the
// tension, which saturates once. Four arms each well inside the word whose sum is beyond it
// raise the TEM flag, and so do arms each beyond the word; RTL and bit-true agree on the
// flags, every particle word and every arm extension.
//
// Volume elements: a squashed tetrahedron's force inside the word raises no flag; its
// coefficient doubled until a force leaves the word raises StatusVolumeSaturated; RTL and
// bit-true agree on the flags and every particle word.
//
// Plate force: the plate-force accumulator keeps 16 guard bits and saturates once when the
// word is sent (StatusPlateSat). Many plate particles each pushing well inside the word
// range add up beyond it: the flag is raised (and only that flag), in both models alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "hls/fixed_format.hpp"
#include "hls/frame_format.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/verilator_transport.hpp"
#include "sim/error.hpp"
#include "sim/model.hpp"

namespace rheo::driver {
namespace {

constexpr int kDegreeLimit = (1 << hls::kForceAccGuardBits) - 1;  // 255

EdgeMaterial soft_material() {
  EdgeMaterial m;
  m.k1 = 100.0;
  m.c1 = 1.0;
  m.c2 = 10.0;
  return m;
}

// A hub particle joined to `leaves` particles 1 m away along +x. hub_is_start: the hub is
// every edge's start (its force-as-start accumulator collects the sums), else their end.
Model star(int leaves, bool hub_is_start) {
  Model m;
  m.floor = false;
  m.gravity = Vec3::Zero();
  m.materials = {soft_material()};
  m.x0.push_back(Vec3(0.0, 0.0, 0.5));
  for (int i = 0; i < leaves; ++i) m.x0.push_back(Vec3(1.0, 0.001 * i, 0.5));
  m.mass.assign(m.x0.size(), 0.01);
  m.flags.assign(m.x0.size(), kFree);
  for (int i = 1; i <= leaves; ++i) {
    Edge e;
    e.s = hub_is_start ? 0 : i;
    e.e = hub_is_start ? i : 0;
    e.l0 = (m.x0[i] - m.x0[0]).norm();
    e.L = e.l0;
    m.edges.push_back(e);
  }
  m.size = 1.0;
  m.height = 0.5;
  return m;
}

struct StepResult {
  std::uint32_t flags = 0;
  std::int32_t plate_word = 0;
  std::vector<std::int32_t> state;  // x[3], p[3] per particle
};

// Loads the image, runs one step with the plate at plate_word and reads back the flags and
// every particle's state. Device::run turns any flag into an error; the flags are what this
// test is about, so the run command goes to the transport and the flags come from the status.
StepResult one_step(Device& dev, const CoreImage& img, std::int32_t plate_word) {
  dev.load(img);
  StepResult r;
  dev.transport().send({frame::header(frame::kOpRun, frame::kRegionGlobals, 1),
                        static_cast<std::uint32_t>(plate_word)});
  r.plate_word = static_cast<std::int32_t>(dev.transport().receive(1).front());
  r.flags = dev.read_status(false).flags;
  r.state = dev.read_particle_state(0, img.num_particles);
  return r;
}

std::unique_ptr<Device> make_device(const std::string& kind, int lanes,
                                    const hls::EdgeElement& element = hls::kThreeElement) {
  if (kind == "bittrue") {
    return std::make_unique<Device>(std::make_unique<BitTrueTransport>(lanes, element));
  }
  VerilatorOptions vo;
  vo.lanes = lanes;
  vo.element = element;
  return std::make_unique<Device>(std::make_unique<VerilatorTransport>(vo));
}

// Every edge's force saturated: the stiffness coefficient raised far beyond the word range
// and each Voigt element stretched by a tenth of its length.
CoreImage saturated_star_image(bool hub_is_start, int lanes) {
  const Model m = star(kDegreeLimit, hub_is_start);
  State s = initial_state(m);
  for (std::size_t k = 0; k < s.d.size(); ++k) s.d[k] = 1.1 * m.edges[k].L;  // stretched
  CoreImage img = make_core_image(m, s, 1e-4, lanes);
  img.materials[0].kt.shift = std::max(-16, img.materials[0].kt.shift - 24);
  return img;
}

struct LimitCase {
  bool hub_is_start;
  int lanes;
};

class ForceAccumulatorLimitTest : public ::testing::TestWithParam<LimitCase> {};

TEST_P(ForceAccumulatorLimitTest, TwoHundredFiftyFiveSaturatedForcesSumWithoutWrapping) {
  const LimitCase c = GetParam();
  const CoreImage img = saturated_star_image(c.hub_is_start, c.lanes);
  const std::int32_t plate = std::int32_t(to_x_word(1.0, img, "plate"));
  auto bittrue = make_device("bittrue", c.lanes);
  const StepResult golden = one_step(*bittrue, img, plate);
  // Every edge force saturated (TEM flag) and the hub's sum beyond the word (MPM flag).
  ASSERT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
  ASSERT_TRUE(golden.flags & hls::kStatusMpmSaturated) << describe_status_flags(golden.flags);
  // The stretched edges pull the hub toward the leaves (+x): p.x > 0. A wrapped sum would
  // have the other sign.
  const std::int32_t hub_px = golden.state[3];
  EXPECT_GT(hub_px, 0);
  // The leaves are pulled back toward the hub.
  EXPECT_LT(golden.state[6 + 3], 0);

  auto rtl = make_device("rtl", c.lanes);
  const StepResult got = one_step(*rtl, img, plate);
  EXPECT_EQ(got.flags, golden.flags) << describe_status_flags(got.flags);
  EXPECT_EQ(got.plate_word, golden.plate_word);
  ASSERT_EQ(got.state.size(), golden.state.size());
  for (std::size_t w = 0; w < got.state.size(); ++w) {
    ASSERT_EQ(got.state[w], golden.state[w]) << "particle " << w / 6 << " word " << w % 6;
  }
}

INSTANTIATE_TEST_SUITE_P(HubSideAndLanes, ForceAccumulatorLimitTest,
                         ::testing::Values(LimitCase{true, 1}, LimitCase{false, 1},
                                           LimitCase{true, 2}, LimitCase{false, 2}),
                         [](const auto& info) {
                           return std::string(info.param.hub_is_start ? "start" : "end") +
                                  "_lanes" + std::to_string(info.param.lanes);
                         });

TEST(ForceAccumulatorLimit, OneEdgeMoreThanTheAccumulatorAllowsIsRefusedByTheHost) {
  const Model m = star(kDegreeLimit + 1, true);
  try {
    make_core_image(m, initial_state(m), 1e-4, 1);
    FAIL() << "degree " << kDegreeLimit + 1 << " accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle 0 has 256 edges"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("at most 255"), std::string::npos) << e.what();
  }
}

// One edge whose material has four Maxwell arms (the parallel arm and three spectrum
// arms), every arm stretched by a tenth of the edge: the arms pull the hub toward the leaf
// (+x). Heavy particles keep the MPM's update far inside its words, so a flag can only come
// from the TEM.
CoreImage stretched_arms_image() {
  Model m = star(1, true);
  m.mass.assign(m.mass.size(), 100.0);
  EdgeMaterial& mat = m.materials[0];
  mat.k2 = 10.0;
  mat.c3 = 10.0;
  mat.spectrum_arms = 3;
  for (int j = 0; j < 3; ++j) mat.spectrum[j] = {10.0, 10.0 * (j + 2)};
  State s = initial_state(m);
  for (int k = 0; k < m.num_edges(); ++k) {
    for (int j = 0; j < 4; ++j) arm_extension(m, s, k, j) = 0.1 * m.edges[k].L;
  }
  return make_core_image(m, s, 1e-4, 1, FormatDesc{}, hls::kThreeElementWith4Arms);
}

// The bit-true run and the RTL run of one step of the core built for the image's element
// agree on the flags, every particle word and every arm extension; returns the bit-true
// result.
StepResult expect_step_matches(const CoreImage& img) {
  const std::int32_t plate = std::int32_t(to_x_word(1.0, img, "plate"));
  auto bittrue = make_device("bittrue", 1, img.element);
  auto rtl = make_device("rtl", 1, img.element);
  const StepResult golden = one_step(*bittrue, img, plate);
  const StepResult got = one_step(*rtl, img, plate);
  EXPECT_EQ(got.flags, golden.flags) << describe_status_flags(got.flags);
  EXPECT_EQ(got.state, golden.state);
  const int slots = static_cast<int>(img.edges.size());
  for (int j = 0; j < img.element.maxwell_arms; ++j) {
    EXPECT_EQ(rtl->read_arm_extensions(j, 0, slots), bittrue->read_arm_extensions(j, 0, slots))
        << "arm " << j;
  }
  return golden;
}

// Steps the bit-true core of the image's element and, while a step raises no flag, applies
// `raise` to the image (at most `tries` times); true once a step raises `flag` (the TEM
// flag unless given). A step that raises another flag first fails the test.
template <class Raise>
bool raise_until_flag(CoreImage& img, int tries, Raise raise,
                      std::uint32_t flag = hls::kStatusTemSaturated) {
  auto bittrue = make_device("bittrue", 1, img.element);
  const std::int32_t plate = std::int32_t(to_x_word(1.0, img, "plate"));
  for (int i = 0; i < tries; ++i) {
    const StepResult r = one_step(*bittrue, img, plate);
    if (r.flags & flag) return true;
    EXPECT_EQ(r.flags, 0u) << describe_status_flags(r.flags);
    if (r.flags != 0u) return false;
    raise(img);
  }
  return false;
}

TEST(ArmForceLimit, FourArmsEachInsideTheWordWhoseSumIsBeyondItSaturateTheTensionOnce) {
  CoreImage img = stretched_arms_image();
  // Raise all four arm springs together, one bit at a time, until the tension saturates.
  // The step before, the four arms (and the Voigt part) summed to less than the word, so
  // each arm alone stays below half the word after the last doubling: only the sum clips.
  const bool reached = raise_until_flag(img, 48, [](CoreImage& i) {
    for (int j = 0; j < 4; ++j) --i.materials[0].k2t[j].shift;
  });
  ASSERT_TRUE(reached) << "the arms' force never saturated the tension";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[3], 0) << "the hub must move toward the leaves (+x)";
}

TEST(ArmForceLimit, ArmsEachBeyondTheWordSaturateAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_arms_image();
  // The largest gain the host allows (shift + the format change >= 0: no left shift).
  for (int j = 0; j < 4; ++j) img.materials[0].k2t[j].shift = -hls::CoefShifts<hls::HardwareFormat>::kK2t;
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[3], 0) << "the hub must move toward the leaves (+x)";
}

// One edge with the force-dependent series damper (seed 000 §3.3), its Voigt spring
// stretched by a tenth of the edge so that the damper thins c2 (f between f1 and f2); heavy
// particles keep the MPM inside its words. The damper core (SeriesDamper = 1).
CoreImage stretched_damper_image() {
  Model m = star(1, true);
  m.mass.assign(m.mass.size(), 100.0);
  EdgeMaterial& mat = m.materials[0];
  mat.nonlinear = true;
  mat.f1 = 1.0;   // N: the spring force k1 |d - L| is 10 N
  mat.f2 = 20.0;
  mat.c2_min = mat.c2 / 8.0;
  State s = initial_state(m);
  for (int k = 0; k < m.num_edges(); ++k) s.d[k] = 1.1 * m.edges[k].L;
  return make_core_image(m, s, 1e-4, 1, FormatDesc{}, hls::kThreeElementWithDamper);
}

TEST(DamperLimit, AnEdgeInsideItsRangeRaisesNoFlagOnEitherModel) {
  const StepResult golden = expect_step_matches(stretched_damper_image());
  EXPECT_EQ(golden.flags, 0u) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[3], 0) << "the stretched edge pulls the hub toward the leaf (+x)";
}

// The slope of z raised one bit at a time until z leaves its word (c2 / c2_max below
// 2^-64, a table the host refuses): the TEM flag on both models, and the same words.
TEST(DamperLimit, ZBeyondItsWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_damper_image();
  const bool reached =
      raise_until_flag(img, 60, [](CoreImage& i) { --i.materials[0].zk.shift; });
  ASSERT_TRUE(reached) << "z never left its word";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// s = c / c_ref made tiny (s_base and s_c2 at their smallest): 1/s would need a coefficient
// shift the packed format does not have; it is clamped and flagged on both models.
TEST(DamperLimit, ACoefficientShiftOutOfRangeIsClampedAndFlaggedOnBothModels) {
  CoreImage img = stretched_damper_image();
  img.materials[0].s_base = hls::Coef{1, 47};
  img.materials[0].s_c2 = hls::Coef{1, 47};
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// One edge with strain hardening, the leaf and the Voigt length pulled out to 1.3 times the
// rest length (strain 0.3: g = 1 + H 0.09); heavy particles keep the MPM inside its words. The hardening core
// (StrainHardening = 1).
CoreImage stretched_hardening_image() {
  Model m = star(1, true);
  m.mass.assign(m.mass.size(), 100.0);
  m.materials[0].hardening = 10.0;
  State s = initial_state(m);
  s.x[1] = m.x0[0] + 1.3 * (m.x0[1] - m.x0[0]);
  s.d[0] = 1.3 * m.edges[0].L;  // the Voigt spring stretched with it
  return make_core_image(m, s, 1e-4, 1, FormatDesc{}, hls::kThreeElementWithHardening);
}

TEST(HardeningLimit, AnEdgeInsideItsRangeRaisesNoFlagOnEitherModel) {
  const StepResult golden = expect_step_matches(stretched_hardening_image());
  EXPECT_EQ(golden.flags, 0u) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[3], 0) << "the stretched edge pulls the hub toward the leaf (+x)";
}

// The hardening coefficient raised one bit at a time until h = H e^2 leaves its word (a
// table the host never writes, g beyond 2^12): the TEM flag on both models, and the same
// words.
TEST(HardeningLimit, StrainTermBeyondItsWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_hardening_image();
  const bool reached =
      raise_until_flag(img, 40, [](CoreImage& i) { --i.materials[0].hk.shift; });
  ASSERT_TRUE(reached) << "h never left its word";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// s_k at its largest packed value (h = 0.9 inside its word): s = 1 + s_k h leaves its word;
// clamped and flagged on both models.
TEST(HardeningLimit, SBeyondItsWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_hardening_image();
  img.materials[0].s_k = hls::Coef{(1 << 17) - 1, -16};
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// One edge with every edge effect: the damper (its spring force, hardened, between f1 and
// f2), strain hardening (strain 0.3) and a Maxwell arm, stretched like the images above. The
// every-effect core (MaxwellArms = 8, SeriesDamper = 1, StrainHardening = 1).
CoreImage stretched_every_effect_image() {
  Model m = star(1, true);
  m.mass.assign(m.mass.size(), 100.0);
  EdgeMaterial& mat = m.materials[0];
  mat.nonlinear = true;
  mat.f1 = 1.0;
  mat.f2 = 40.0;
  mat.c2_min = mat.c2 / 8.0;
  mat.hardening = 10.0;
  mat.k2 = 0.5 * mat.k1;
  mat.c3 = 0.5 * mat.c2;
  State s = initial_state(m);
  s.x[1] = m.x0[0] + 1.3 * (m.x0[1] - m.x0[0]);
  s.d[0] = 1.3 * m.edges[0].L;
  arm_extension(m, s, 0, 0) = 0.1 * m.edges[0].L;
  return make_core_image(m, s, 1e-4, 1, FormatDesc{}, hls::kThreeElementEveryEffect);
}

TEST(EveryEffectLimit, AnEdgeInsideItsRangeRaisesNoFlagOnEitherModel) {
  const StepResult golden = expect_step_matches(stretched_every_effect_image());
  EXPECT_EQ(golden.flags, 0u) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[3], 0) << "the stretched edge pulls the hub toward the leaf (+x)";
}

// h beyond its word with the damper behind it: z then follows the clamped g |d - L|.
TEST(EveryEffectLimit, StrainTermBeyondItsWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_every_effect_image();
  const bool reached =
      raise_until_flag(img, 40, [](CoreImage& i) { --i.materials[0].hk.shift; });
  ASSERT_TRUE(reached) << "h never left its word";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// z of the damper behind the hardening unit beyond its word.
TEST(EveryEffectLimit, ZBeyondItsWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_every_effect_image();
  const bool reached =
      raise_until_flag(img, 60, [](CoreImage& i) { --i.materials[0].zk.shift; });
  ASSERT_TRUE(reached) << "z never left its word";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// The arm's spring raised until the tension (with the hardened, damped terms) saturates.
TEST(EveryEffectLimit, ArmForceBeyondTheWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = stretched_every_effect_image();
  const bool reached =
      raise_until_flag(img, 48, [](CoreImage& i) { --i.materials[0].k2t[0].shift; });
  ASSERT_TRUE(reached) << "the tension never saturated";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusTemSaturated) << describe_status_flags(golden.flags);
}

// One tetrahedron (dim 3: its six edges and its volume force) or one triangle of a 2-D
// model (dim 2: its three edges and its area force) with its apex, the last vertex, pressed
// to 70 % of its height, on the core with volume elements.
CoreImage squashed_element_image(int dim) {
  Model m;
  m.dim = dim;
  m.floor = false;
  m.gravity = Vec3::Zero();
  m.materials = {soft_material()};
  m.x0 = {Vec3(0.0, 0.0, 0.5), Vec3(1.0, 0.0, 0.5)};
  if (dim == 3) m.x0.push_back(Vec3(0.0, 1.0, 0.5));
  m.x0.push_back(Vec3(0.0, 0.0, 1.5));
  const int n = dim + 1;
  m.mass.assign(std::size_t(n), 100.0);
  m.flags.assign(std::size_t(n), kFree);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      Edge e;
      e.s = a;
      e.e = b;
      e.l0 = e.L = (m.x0[b] - m.x0[a]).norm();
      m.edges.push_back(e);
    }
  }
  if (dim == 3) m.tetrahedra = {{0, 1, 2, 3}};
  else m.triangles = {{0, 1, 2}};
  m.volume.enabled = true;
  m.volume.kv = 100.0;
  m.size = 1.0;
  m.height = 1.5;
  State s = initial_state(m);
  s.x[std::size_t(dim)].z() = 1.2;
  return make_core_image(m, s, 1e-4, 1, FormatDesc{}, hls::kThreeElementWithVolume);
}

// The element's coefficient (the second half's L word) times two.
void double_volume_coefficient(CoreImage& img) {
  for (hls::EdgeEntry& e : img.edges) {
    if (!(e.element && e.second)) continue;
    hls::Coef c = hls::unpack_coef(std::uint32_t(e.L));
    --c.shift;
    e.L = std::int64_t((std::uint32_t(c.shift + hls::kCoefShiftBias) << frame::kCoefShiftPos) |
                       (std::uint32_t(c.mant) & ((1u << hls::kCoefMantBits) - 1)));
  }
}

// A squashed tetrahedron (3-D) and a squashed triangle (2-D).
struct SquashedElement {
  const char* name;
  int dim;
};
class VolumeLimit : public ::testing::TestWithParam<SquashedElement> {};

TEST_P(VolumeLimit, AnElementInsideItsRangeRaisesNoFlagOnEitherModel) {
  const StepResult golden = expect_step_matches(squashed_element_image(GetParam().dim));
  EXPECT_EQ(golden.flags, 0u) << describe_status_flags(golden.flags);
  EXPECT_GT(golden.state[std::size_t(GetParam().dim) * 6 + 5], 0)
      << "the squashed element pushes its apex up (+z)";
}

TEST_P(VolumeLimit, AForceBeyondTheWordSaturatesAndRtlAndBitTrueAgree) {
  CoreImage img = squashed_element_image(GetParam().dim);
  const bool reached = raise_until_flag(img, 40, double_volume_coefficient,
                                            hls::kStatusVolumeSaturated);
  ASSERT_TRUE(reached) << "the element's force never left its word";
  const StepResult golden = expect_step_matches(img);
  EXPECT_TRUE(golden.flags & hls::kStatusVolumeSaturated) << describe_status_flags(golden.flags);
}

INSTANTIATE_TEST_SUITE_P(
    Elements, VolumeLimit,
    ::testing::Values(SquashedElement{"tetrahedron", 3}, SquashedElement{"triangle", 2}),
    [](const ::testing::TestParamInfo<SquashedElement>& info) {
      return std::string(info.param.name);
    });

// `pairs` plate particles at z = 0.5 m, each hanging from a fixed anchor 0.25 m above by a
// stretched edge: each is pulled up through the plate (at 0.5 m), held by it, and adds
// its upward force to the plate force.
Model hanging_plate_particles(int pairs) {
  Model m;
  m.floor = false;
  m.gravity = Vec3::Zero();
  m.materials = {soft_material()};
  for (int i = 0; i < pairs; ++i) {
    m.x0.push_back(Vec3(0.01 * i, 0.0, 0.75));  // anchor
    m.x0.push_back(Vec3(0.01 * i, 0.0, 0.5));   // plate particle
    m.flags.push_back(kFixed);
    m.flags.push_back(kPlate);
    Edge e;
    e.s = 2 * i;
    e.e = 2 * i + 1;
    e.l0 = e.L = 0.25;
    m.edges.push_back(e);
  }
  m.mass.assign(m.x0.size(), 0.01);
  m.size = 1.0;
  m.height = 0.5;
  return m;
}

class PlateSaturationTest : public ::testing::TestWithParam<int> {};

TEST_P(PlateSaturationTest, ManyPlateParticlesInsideTheWordRangeSaturateThePlateSum) {
  const int lanes = GetParam();
  constexpr int kPairs = 64;
  const Model m = hanging_plate_particles(kPairs);
  State s = initial_state(m);
  for (std::size_t k = 0; k < s.d.size(); ++k) s.d[k] = 1.2 * m.edges[k].L;
  CoreImage img = make_core_image(m, s, 1e-4, lanes);
  const std::int32_t plate = std::int32_t(to_x_word(0.5, img, "plate"));

  // Scale the stiffness coefficient until each particle's force is a sizeable fraction of
  // the word but 64 of them exceed it: 2^31 / 64 < f.z < 2^31.
  auto bittrue = make_device("bittrue", lanes);
  StepResult golden;
  bool reached = false;
  for (int raise = 0; raise < 40 && !reached; ++raise) {
    golden = one_step(*bittrue, img, plate);
    if (golden.flags & hls::kStatusPlateSaturated) {
      reached = true;
      break;
    }
    ASSERT_EQ(golden.flags, 0u) << describe_status_flags(golden.flags);
    --img.materials[0].kt.shift;
  }
  ASSERT_TRUE(reached) << "the plate sum never saturated";
  // Only the plate flag: every particle's own force stayed inside the word.
  EXPECT_EQ(golden.flags, std::uint32_t(hls::kStatusPlateSaturated))
      << describe_status_flags(golden.flags);
  // Saturated to the largest positive word (the particles push the plate up).
  EXPECT_EQ(golden.plate_word, std::numeric_limits<std::int32_t>::max());

  auto rtl = make_device("rtl", lanes);
  const StepResult got = one_step(*rtl, img, plate);
  EXPECT_EQ(got.flags, golden.flags) << describe_status_flags(got.flags);
  EXPECT_EQ(got.plate_word, golden.plate_word);
  ASSERT_EQ(got.state, golden.state);
}

INSTANTIATE_TEST_SUITE_P(Lanes, PlateSaturationTest, ::testing::Values(1, 2, 4));

}  // namespace
}  // namespace rheo::driver
