// Overlapped steps on the sweep core (host/driver/sweep_overlap.cpp): the least period at
// which the next step of a command may start, from every access of two steps. The RTL
// runs at this period (hw_sweep_cosim_test: bit-exact, clocks = formula, and flagged two
// clocks below it).
#include <gtest/gtest.h>

#include <algorithm>

#include "host/driver/sweep_image.hpp"
#include "host/driver/sweep_overlap.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::driver {
namespace {

SweepImage image_of(const Scenario& s, int lanes) {
  const Model model = orient_edges_low_to_high(s.build_model());
  SweepCoreShape shape;
  shape.lanes = lanes;
  return make_sweep_image(model, initial_state(model), s.options.dt, shape);
}

long longest_stream(const SweepImage& img) {
  long longest = 0;
  for (int j = 0; j < img.lanes_used; ++j)
    longest = std::max(longest, long(img.lane[j].delay) + img.lane[j].slots);
  return hls::kSweepLeadClocks + longest;
}

// The lattices the core is sized for: the next step can start before the last one drains.
TEST(SweepOverlap, LatticesOverlapTheirStepsAtAnEvenPeriodAboveEveryBound) {
  for (const char* name : {"block5", "block15"}) {
    const SweepImage img = image_of(load_scenario(name), 5);
    const SweepOverlap o = sweep_overlap(img);
    EXPECT_EQ(o.stream_bound, longest_stream(img)) << name;
    EXPECT_GE(o.period, std::max(o.stream_bound, o.hazard_bound)) << name;
    EXPECT_EQ(o.period % 2, 0) << name;
    EXPECT_LT(o.period, img.cycles_per_step) << name;
    RecordProperty(std::string(name) + "_period", std::to_string(o.period));
    std::printf("%s: %ld clocks per step alone, period %ld (stream bound %ld, hazard bound %ld: %s; %s)\n",
                name, img.cycles_per_step, o.period, o.stream_bound, o.hazard_bound,
                o.hazard.c_str(), o.binding.c_str());
  }
}

// Reading the MPM's queue entry from the ghost memory's port A at the MPM's own clock (the
// lane before 2 Dec 2026), the next step's ghost reads meet it; reading two entries ahead
// whenever the port is free, as the lane does, removes every clash.
TEST(SweepOverlap, TheQueueReadAtAFixedClockMeetsTheNextStepsGhostReads) {
  const SweepImage img = image_of(load_scenario("block5"), 5);
  const SweepOverlap fixed = sweep_overlap(img, 0);
  const SweepOverlap ahead = sweep_overlap(img, 2);
  EXPECT_NE(fixed.binding.find("a ghost read and the MPM's queue read"), std::string::npos)
      << fixed.binding;
  EXPECT_GT(fixed.period, ahead.period);
  EXPECT_EQ(ahead.period, ahead.stream_bound + ahead.stream_bound % 2) << ahead.binding;
  std::printf("block5: queue read at its clock %ld (%s), two ahead %ld\n", fixed.period,
              fixed.binding.c_str(), ahead.period);
}

// A short stream: each particle's x and p are written back a pipeline after its slots, long
// after the next step would read them, so that hazard, not the stream, sets the period.
TEST(SweepOverlap, AShortStreamWaitsForItsParticlesWriteBack) {
  Scenario s = load_scenario("block5");
  s.block.nx = 2;
  s.block.ny = 2;
  s.block.nz = 2;
  const SweepImage img = image_of(s, 1);
  const SweepOverlap o = sweep_overlap(img);
  EXPECT_LT(o.stream_bound, o.hazard_bound);
  EXPECT_NE(o.binding.find("x/p"), std::string::npos) << o.binding;
  // A particle's x/p read (its first slot + 3) and its write-back (its last slot + the
  // pipeline to the MPM's output + 2): at least the pipeline apart.
  EXPECT_GE(o.hazard_bound, hls::kSweepSramClocks + 1 + hls::kTemLatency + 4 + hls::kMpmLatency);
  EXPECT_LE(o.period, img.cycles_per_step);
}

}  // namespace
}  // namespace rheo::driver
