// The core's stream ports under random idle cycles on s_axis and random back-pressure on
// m_axis, for 1, 2 and 4 lanes: results stay bit-identical to the bit-true model; commands
// with no data, read-back and status behave as the frame format says; an overflow raised
// by the core reaches the host as rheo::Error.
#include <gtest/gtest.h>

#include <memory>

#include "host/driver/bittrue_transport.hpp"
#include "host/cosim/cosim.hpp"
#include "host/driver/device.hpp"
#include "hls/frame_format.hpp"
#include "host/driver/verilator_transport.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"

namespace rheo::driver {
namespace {

using cosim::CosimOptions;
using cosim::CosimResult;
using cosim::run_cosim;

// A 3 x 3 x 3 version of block5 keeps the runs short.
Scenario small_block() {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = 3;
  return s;
}

constexpr long kStreamSteps = 300;
// Heavy stalls on both sides: every handshake pattern occurs many times.
constexpr double kIdleProb = 0.4;
constexpr double kStallProb = 0.5;

class StreamTest : public ::testing::TestWithParam<int> {};

TEST_P(StreamTest, RandomIdleAndBackPressureOnBothSidesKeepResultsBitExact) {
  CosimOptions opt;
  opt.steps = kStreamSteps;
  opt.lanes = GetParam();
  opt.input_idle_prob = kIdleProb;
  opt.output_stall_prob = kStallProb;
  opt.seed = 1234 + GetParam();
  opt.run_reference = false;
  const CosimResult r = run_cosim(small_block(), opt);
  ASSERT_EQ(r.mismatches, 0) << r.first.front().describe();
  EXPECT_EQ(r.steps, kStreamSteps);
  // Stalls must not change the compute clocks (they are counted only while busy).
  EXPECT_DOUBLE_EQ(r.cycles_per_step_measured, double(r.cycles_per_step_formula));
}

INSTANTIATE_TEST_SUITE_P(Lanes, StreamTest, ::testing::Values(1, 2, 4));

// The long run: thousands of steps of random idle cycles and back-pressure, with the stream
// checker's assertions on, so that rare orderings of a stall against a state change of the
// command FSM occur; the state is compared every 25 steps (a read-back between steps also
// stalls the stream).
constexpr long kLongStreamSteps = 5000;

class LongStreamTest : public ::testing::TestWithParam<int> {};

TEST_P(LongStreamTest, ThousandsOfStepsOfRandomStallsStayBitExact) {
  CosimOptions opt;
  opt.steps = kLongStreamSteps;
  opt.lanes = GetParam();
  opt.compare_every = 25;
  opt.input_idle_prob = 0.3;
  opt.output_stall_prob = 0.6;
  opt.seed = 777 + GetParam();
  opt.run_reference = false;
  const CosimResult r = run_cosim(small_block(), opt);
  ASSERT_EQ(r.mismatches, 0) << r.first.front().describe();
  EXPECT_EQ(r.steps, kLongStreamSteps);
  EXPECT_DOUBLE_EQ(r.cycles_per_step_measured, double(r.cycles_per_step_formula));
}

INSTANTIATE_TEST_SUITE_P(Lanes, LongStreamTest, ::testing::Values(1, 2, 4));

std::unique_ptr<Device> rtl_device(int lanes, VerilatorTransport** raw = nullptr) {
  VerilatorOptions vo;
  vo.lanes = lanes;
  vo.input_idle_prob = kIdleProb;
  vo.output_stall_prob = kStallProb;
  auto t = std::make_unique<VerilatorTransport>(vo);
  if (raw) *raw = t.get();
  return std::make_unique<Device>(std::move(t));
}

TEST(Stream, StatusCountsStepsReadsBackAndClearsOnRequest) {
  const Scenario s = small_block();
  const Model m = s.build_model();
  const CoreImage img = make_core_image(m, initial_state(m), s.options.dt, 1);
  VerilatorTransport* raw = nullptr;
  auto dev = rtl_device(1, &raw);
  dev->load(img);
  // Read-back of what was loaded: the Voigt lengths start at d = L (edge slots).
  const std::vector<std::int32_t> d = dev->read_voigt_lengths(0, 4);
  for (int t = 0; t < 4; ++t) EXPECT_EQ(d[t], img.edges[t].L);
  const std::int32_t above = std::int32_t(to_x_word(m.height + 0.001, img, "plate"));
  dev->run({above, above, above});
  CoreStatus st = dev->read_status(false);
  EXPECT_EQ(st.step_count, 3u);
  EXPECT_EQ(st.lanes, 1u);
  EXPECT_EQ(st.flags, 0u);
  // A set flag survives a plain read and is gone after read-and-clear.
  dev->transport().send({0xF0000000u});
  EXPECT_TRUE(dev->read_status(true).flags & hls::kStatusBadCommand);
  st = dev->read_status(false);
  EXPECT_EQ(st.flags, 0u);
  // m_axis_tlast closes every response: load's status (4), the read (4), the run (3), then
  // the statuses (4 each).
  const std::vector<std::size_t> expected = {4, 4, 3, 4, 4, 4, 4};
  EXPECT_EQ(raw->output_frame_lengths(), expected);
}

TEST(Stream, UnknownOpcodeRaisesTheBadCommandFlag) {
  auto dev = rtl_device(1);
  dev->transport().send({0xF0000000u});
  const CoreStatus st = dev->read_status(false);
  EXPECT_TRUE(st.flags & hls::kStatusBadCommand);
}

class SaturationTest : public ::testing::TestWithParam<bool> {};

TEST_P(SaturationTest, ForcedOverflowIsReportedByTheHostAsAnError) {
  const Scenario s = small_block();
  const Model m = s.build_model();
  CoreImage img = make_core_image(m, initial_state(m), s.options.dt, 1);
  // Gravity of almost one length unit per step^2: p saturates within two steps.
  img.globals.g[2] = -(std::int64_t(1) << 30);
  std::unique_ptr<Device> dev =
      GetParam() ? rtl_device(1) : std::make_unique<Device>(std::make_unique<BitTrueTransport>(1));
  dev->load(img);
  const std::int32_t above = std::int32_t(to_x_word(m.height + 0.001, img, "plate"));
  try {
    dev->run(std::vector<std::int32_t>(4, above));
    FAIL() << "overflow not reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("MPM result saturated"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(RtlAndBitTrue, SaturationTest, ::testing::Values(true, false));

// A crafted image whose schedule puts two end particles of one row in the same bank: the
// crossbar cannot serve the row, and the core must say so instead of computing silently.
class ScheduleConflictTest : public ::testing::TestWithParam<bool> {};

TEST_P(ScheduleConflictTest, TwoEndsInOneBankInOneRowRaiseTheScheduleFlag) {
  const Scenario s = small_block();
  const Model m = s.build_model();
  CoreImage img = make_core_image(m, initial_state(m), s.options.dt, 2);
  bool crafted = false;
  for (int r = 0; r < img.edge_rows && !crafted; ++r) {
    hls::EdgeEntry& a = img.edges[std::size_t(r) * 2];
    hls::EdgeEntry& b = img.edges[std::size_t(r) * 2 + 1];
    if (a.valid && b.valid) {
      b.e_bank = a.e_bank;
      b.e_local = a.e_local;
      crafted = true;
    }
  }
  ASSERT_TRUE(crafted);
  std::unique_ptr<Device> dev =
      GetParam() ? rtl_device(2) : std::make_unique<Device>(std::make_unique<BitTrueTransport>(2));
  dev->load(img);
  const std::int32_t above = std::int32_t(to_x_word(m.height + 0.001, img, "plate"));
  try {
    dev->run({above});
    FAIL() << "schedule conflict not reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("edge schedule conflict"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(RtlAndBitTrue, ScheduleConflictTest, ::testing::Values(true, false));

// Particle or row counts beyond the memories would wrap the addresses: refused.
class CountRangeTest : public ::testing::TestWithParam<bool> {};

TEST_P(CountRangeTest, CountsBeyondTheMemoriesRaiseTheBadCommandFlag) {
  std::unique_ptr<Device> dev =
      GetParam() ? rtl_device(1) : std::make_unique<Device>(std::make_unique<BitTrueTransport>(1));
  for (const auto& [reg, value] :
       {std::pair{frame::kGlobalNumParticles, std::uint32_t(hls::kMaxParticles) + 1},
        std::pair{frame::kGlobalEdgeRows, std::uint32_t(hls::kMaxEdges) + 1}}) {
    dev->transport().send({frame::header(frame::kOpWrite, frame::kRegionGlobals, 1), reg, value});
    EXPECT_TRUE(dev->read_status(true).flags & hls::kStatusBadCommand) << reg;
  }
  // The largest counts the memories hold are accepted.
  dev->transport().send({frame::header(frame::kOpWrite, frame::kRegionGlobals, 2),
                         frame::kGlobalNumParticles, std::uint32_t(hls::kMaxParticles),
                         std::uint32_t(hls::kMaxEdges)});
  EXPECT_EQ(dev->read_status(true).flags, 0u);
}

INSTANTIATE_TEST_SUITE_P(RtlAndBitTrue, CountRangeTest, ::testing::Values(true, false));

}  // namespace
}  // namespace rheo::driver
