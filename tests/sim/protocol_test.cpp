#include <gtest/gtest.h>

#include "sim/error.hpp"
#include "sim/protocol.hpp"

namespace rheo {
namespace {

constexpr double kRoundoff = 1e-12;

TEST(PushHoldRelease, PushesAtTheGivenSpeedHoldsAndRetracts) {
  // seed 002: 9.6 mm at 0.5 mm/s (19.2 s), hold 47.88 s, release, 10 s after.
  const PlateProtocol p = PlateProtocol::push_hold_release(9.6, 0.5, 47.88, 10.0);
  EXPECT_NEAR(p.duration(), 19.2 + 47.88 + 19.2 + 10.0, kRoundoff);
  EXPECT_NEAR(p.displacement_mm(0.0), 0.0, kRoundoff);
  EXPECT_NEAR(p.displacement_mm(10.0), 5.0, kRoundoff);
  EXPECT_NEAR(p.displacement_mm(19.2), 9.6, kRoundoff);
  EXPECT_NEAR(p.displacement_mm(40.0), 9.6, kRoundoff);
  EXPECT_NEAR(p.displacement_mm(19.2 + 47.88 + 9.6), 4.8, 1e-9);
  EXPECT_NEAR(p.displacement_mm(p.duration() - 1.0), 0.0, kRoundoff);
}

TEST(PlateProtocol, IsConstantBeyondItsEnds) {
  PlateProtocol p;
  p.t = {0.0, 1.0, 2.0};
  p.plate_mm = {0.5, 1.5, 1.0};
  EXPECT_EQ(p.displacement_mm(-3.0), 0.5);
  EXPECT_EQ(p.displacement_mm(5.0), 1.0);
  EXPECT_NEAR(p.displacement_mm(1.5), 1.25, kRoundoff);
}

TEST(PlateProtocol, WithoutKnotsTheDisplacementIsZero) {
  EXPECT_EQ(PlateProtocol{}.displacement_mm(1.0), 0.0);
  EXPECT_EQ(PlateProtocol{}.duration(), 0.0);
}

TEST(PushHoldRelease, SkipsAnEmptyHoldAndKeepsTimesIncreasing) {
  const PlateProtocol p = PlateProtocol::push_hold_release(1.0, 1.0, 0.0, 0.0);
  for (std::size_t i = 1; i < p.t.size(); ++i) EXPECT_GT(p.t[i], p.t[i - 1]);
  EXPECT_NEAR(p.displacement_mm(1.0), 1.0, kRoundoff);
}

TEST(PushHoldRelease, RejectsANonPositiveSpeed) {
  EXPECT_THROW(PlateProtocol::push_hold_release(1.0, 0.0, 1.0, 1.0), Error);
  EXPECT_THROW(PlateProtocol::push_hold_release(-1.0, 1.0, 1.0, 1.0), Error);
}

}  // namespace
}  // namespace rheo

namespace rheo {
namespace {

TEST(PlateProtocolPhases, PushHoldReleaseGivesItsFourPhasesWithTheirTimes) {
  const PlateProtocol p = PlateProtocol::push_hold_release(8.0, 4.0, 3.0, 3.0);
  const std::vector<ProtocolPhase> phases = p.phases();
  ASSERT_EQ(phases.size(), 4u);
  EXPECT_EQ(phases[0].kind, PhaseKind::kPush);
  EXPECT_EQ(phases[1].kind, PhaseKind::kHold);
  EXPECT_EQ(phases[2].kind, PhaseKind::kRelease);
  EXPECT_EQ(phases[3].kind, PhaseKind::kRest);
  EXPECT_DOUBLE_EQ(phases[0].t_end, 2.0);
  EXPECT_DOUBLE_EQ(phases[1].t_end, 5.0);
  EXPECT_DOUBLE_EQ(phases[2].t_end, 7.0);
  EXPECT_DOUBLE_EQ(phases[3].t_end, 10.0);
  EXPECT_STREQ(phase_name(phases[1].kind), "hold");
}

TEST(PlateProtocolPhases, MergesNeighbouringSegmentsOfOneKind) {
  PlateProtocol p;
  p.t = {0.0, 1.0, 2.0, 3.0, 4.0};
  p.plate_mm = {0.0, 1.0, 3.0, 3.0, 3.0};  // two push speeds, two hold knots
  const std::vector<ProtocolPhase> phases = p.phases();
  ASSERT_EQ(phases.size(), 2u);
  EXPECT_EQ(phases[0].kind, PhaseKind::kPush);
  EXPECT_DOUBLE_EQ(phases[0].t_end, 2.0);
  EXPECT_EQ(phases[1].kind, PhaseKind::kHold);
}

}  // namespace
}  // namespace rheo
