// The run summary reads figures per protocol phase, not over the whole run.
#include "host/output/run_summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace rheo::output {
namespace {

constexpr double kNoSurface = std::numeric_limits<double>::quiet_NaN();

// push 0-2 s, hold 2-5 s, release 5-7 s, rest 7-10 s.
RunSummary push_hold_release_run() {
  RunSummary s(PlateProtocol::push_hold_release(8.0, 4.0, 3.0, 3.0));
  s.add(0.0, 0.0, 0.0);
  s.add(0.002, 9.0, kNoSurface);  // a start-up transient larger than the push peak
  s.add(1.0, 3.0, kNoSurface);
  s.add(2.0, 7.0, 8.0);  // end of push: its peak
  s.add(3.5, 5.0, kNoSurface);
  s.add(5.0, 3.5, 8.0);  // end of hold
  s.add(5.5, 1.0, kNoSurface);
  s.add(6.0, 0.0, kNoSurface);  // plate leaves the object
  s.add(8.0, 0.0, 3.2);
  s.add(10.0, 0.0, kNoSurface);  // positions not read back at the last step
  return s;
}

TEST(RunSummaryTest, PushReportsTheForceItBuildsUpToAndNamesAnEarlierLargerForceATransient) {
  const std::vector<std::string> lines = push_hold_release_run().lines();
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0],
            "push 0-2 s: force at the end 7 N (t = 2 s); an early transient reaches 9 N at "
            "t = 0.002 s");
}

TEST(RunSummaryTest, ARisingPushNamesNoTransient) {
  RunSummary s(PlateProtocol::push_hold_release(8.0, 4.0, 3.0, 3.0));
  s.add(1.0, 3.0, kNoSurface);
  s.add(2.0, 7.0, kNoSurface);
  EXPECT_EQ(s.lines()[0], "push 0-2 s: force at the end 7 N (t = 2 s)");
}

TEST(RunSummaryTest, ReportsHoldEndForceContactLossAndResidualDeformation) {
  const std::vector<std::string> lines = push_hold_release_run().lines();
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_NE(
      lines[1].find("hold 2-5 s: force at the end 3.5 N (t = 5 s), 50 % of the push's end force"),
      std::string::npos)
      << lines[1];
  EXPECT_NE(lines[2].find("the plate leaves the object at t = 6 s"), std::string::npos) << lines[2];
  // The last known surface reading, with its time, is the residual deformation.
  EXPECT_NE(lines[3].find("residual deformation 3.2 mm (top surface at t = 8 s, 1 s after "
                          "release)"),
            std::string::npos)
      << lines[3];
}

// block5's release: the object leaves the rising plate, springs back and touches it again
// for a second: the separation reported is the last one, and the touches are counted.
TEST(RunSummaryTest, AReleaseThatTouchesAgainReportsTheLastSeparation) {
  RunSummary s(PlateProtocol::push_hold_release(8.0, 4.0, 3.0, 3.0));
  s.add(2.0, 7.0, kNoSurface);
  s.add(5.0, 3.5, kNoSurface);
  s.add(5.001, 0.0, kNoSurface);  // leaves
  s.add(5.03, 1.94, kNoSurface);  // touches again
  s.add(6.0, 0.5, kNoSurface);
  s.add(6.07, 0.0, kNoSurface);  // leaves for good
  s.add(6.5, 0.0, kNoSurface);
  const std::vector<std::string> lines = s.lines();
  ASSERT_GE(lines.size(), 3u);
  EXPECT_NE(lines[2].find("the plate leaves the object at t = 6.07 s (it first left at t = 5.001 "
                          "s; the object touched the plate again 1 time)"),
            std::string::npos)
      << lines[2];
}

TEST(RunSummaryTest, ARunThatEndsInTheHoldSaysThePlateIsNotYetReleased) {
  RunSummary s(PlateProtocol::push_hold_release(8.0, 4.0, 3.0, 3.0));
  s.add(1.0, 3.0, 4.0);
  s.add(3.0, 2.0, 8.0);
  const std::vector<std::string> lines = s.lines();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[1].find("hold 2-3 s"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("plate not yet released"), std::string::npos) << lines[1];
}

}  // namespace
}  // namespace rheo::output
