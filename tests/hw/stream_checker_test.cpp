// The stream checker (rtl/rheo_stream_checker.sv) fires: a testbench that withdraws
// s_axis_tvalid before the core took the word must stop the simulation with the input
// port's assertion, and the same testbench holding the word until it is taken must not.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_core_l1.h"
#pragma GCC diagnostic pop

#include <memory>
#include <string>

#include "hls/frame_format.hpp"

namespace rheo {
namespace {

// Drives the one-lane core directly: after reset it clears its force sums (input not
// ready for MaxParticles clocks), so a word offered right after reset is stalled.
struct Bench {
  Bench() : ctx(std::make_unique<VerilatedContext>()) {
    ctx->fatalOnError(false);
    core = std::make_unique<Vrheo_core_l1>(ctx.get(), "rheo_core");
    core->clk_i = 0;
    core->rst_ni = 1;
    core->eval();
    core->rst_ni = 0;  // falling edge: the asynchronous reset acts at once
    core->eval();
    for (int i = 0; i < 4; ++i) tick();
    core->rst_ni = 1;
    tick();
  }
  ~Bench() { core->final(); }
  void tick() {
    core->clk_i = 0;
    core->eval();
    core->clk_i = 1;
    core->eval();
  }
  std::unique_ptr<VerilatedContext> ctx;
  std::unique_ptr<Vrheo_core_l1> core;
};

// Offers a STATUS command while the core is not ready; `hold` keeps it offered until it
// is taken, otherwise it is withdrawn after `offered` clocks. Returns what the
// simulation printed.
std::string offer_status_command(bool hold, int offered, bool* failed) {
  ::testing::internal::CaptureStdout();
  {
    Bench b;
    b.core->m_axis_tready = 1;
    b.core->s_axis_tdata = frame::header(frame::kOpStatus, frame::kRegionGlobals, 0);
    b.core->s_axis_tvalid = 1;
    b.core->s_axis_tlast = 1;
    for (int clk = 0; clk < 8192 && !b.ctx->gotError(); ++clk) {
      b.core->clk_i = 0;
      b.core->eval();
      const bool taken = b.core->s_axis_tvalid && b.core->s_axis_tready;
      b.core->clk_i = 1;
      b.core->eval();
      if (taken || (!hold && clk + 1 >= offered)) {
        b.core->s_axis_tvalid = 0;
        b.core->s_axis_tlast = 0;
      }
      if (taken) break;
    }
    for (int clk = 0; clk < 4 && !b.ctx->gotError(); ++clk) b.tick();
    *failed = b.ctx->gotError();
  }
  return ::testing::internal::GetCapturedStdout();
}

TEST(StreamChecker, WithdrawingAStalledInputWordFailsTheInputAssertion) {
  bool failed = false;
  const std::string out = offer_status_command(false, 3, &failed);
  EXPECT_TRUE(failed);
  EXPECT_NE(out.find("s_axis: testbench withdrew or changed a word before s_axis_tready"),
            std::string::npos)
      << out;
}

TEST(StreamChecker, HoldingAStalledInputWordUntilTakenPasses) {
  bool failed = true;
  const std::string out = offer_status_command(true, 0, &failed);
  EXPECT_FALSE(failed) << out;
}

}  // namespace
}  // namespace rheo
