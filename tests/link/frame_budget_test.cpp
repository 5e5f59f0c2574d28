// FrameBudget (host/driver/link/frame_budget.hpp): what a command frame costs, the server's
// refusal of a frame over the limits (summed over its commands), and the host's cut of any
// command stream into frames within them.
#include "host/driver/link/frame_budget.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hls/frame_format.hpp"
#include "host/driver/link/link_error.hpp"

namespace rheo::link {
namespace {

std::uint32_t read(frame::Region region, std::uint32_t count) {
  return frame::header(frame::kOpRead, region, count);
}
std::uint32_t run(std::uint32_t steps) {
  return frame::header(frame::kOpRun, frame::kRegionGlobals, steps);
}
std::uint32_t status() { return frame::header(frame::kOpStatus, frame::kRegionGlobals, 0); }

// The refusal's message, or "" when the frame was accepted.
std::string refusal(FrameBudget& budget, const std::vector<std::uint32_t>& words) {
  try {
    budget.weigh(words, 7);
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kOverLimit) << e.what();
    return e.what();
  }
  return "";
}

TEST(FrameBudget, CountsAnswerWordsStepsAndWordsOfEachCommand) {
  FrameBudget budget;
  const std::vector<std::uint32_t> words = {
      frame::header(frame::kOpWrite, frame::kRegionParticleState, 1), 0, 1, 2, 3, 4, 5, 6,
      run(3), 10, 11, 12,
      read(frame::kRegionMaterial, 10), 0,
      status()};
  const FrameCost cost = budget.weigh(words, 1);
  EXPECT_EQ(cost.words, words.size());
  EXPECT_EQ(cost.steps, 3u);
  EXPECT_EQ(cost.answer_words, 3u + 10u * 7u + frame::kStatusWords);
}

TEST(FrameBudget, AHugeReadIsRefusedNamingTheFrameTheCommandAndTheLimits) {
  FrameBudget budget;
  const std::string text = refusal(budget, {read(frame::kRegionMaterial, 0xFFFFFF), 0});
  EXPECT_NE(text.find("over the server's limits: command frame 7: by its word 1 (in a READ of "
                      "16777215 entries of region 4, 7 words each) its commands ask for "
                      "117440505 response words"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("at most " + std::to_string(kMaxAnswerWordsPerFrame) +
                      " response words and " + std::to_string(kMaxStepsPerFrame) + " steps"),
            std::string::npos)
      << text;
}

TEST(FrameBudget, TheLimitsHoldForTheSumOverTheFramesCommands) {
  const std::uint32_t quarter = static_cast<std::uint32_t>(kMaxAnswerWordsPerFrame / 4);
  std::vector<std::uint32_t> reads;
  for (int i = 0; i < 4; ++i) reads.insert(reads.end(), {read(frame::kRegionEdgeLength, quarter), 0});
  FrameBudget at_limit;
  EXPECT_EQ(refusal(at_limit, reads), "");
  reads.push_back(status());
  FrameBudget over;
  EXPECT_NE(refusal(over, reads).find("by its word 8 (in a STATUS)"), std::string::npos);

  std::vector<std::uint32_t> runs;
  for (std::uint32_t i = 0; i < 2; ++i) {
    runs.push_back(run(static_cast<std::uint32_t>(kMaxStepsPerFrame / 2)));
    runs.resize(runs.size() + kMaxStepsPerFrame / 2, 0);
  }
  FrameBudget steps_at_limit;
  EXPECT_EQ(refusal(steps_at_limit, runs), "");
  runs.insert(runs.end(), {run(1), 0});
  FrameBudget steps_over;
  EXPECT_NE(refusal(steps_over, runs).find("it runs " + std::to_string(kMaxStepsPerFrame + 1) +
                                           " steps"),
            std::string::npos);
}

TEST(FrameBudget, ACommandSpanningFramesCountsInTheFrameOfTheWordThatMakesItOwed) {
  FrameBudget budget;
  const std::uint32_t header = read(frame::kRegionMaterial, 0xFFFFFF);
  EXPECT_EQ(budget.weigh(std::vector<std::uint32_t>{header}, 1).answer_words, 0u);
  EXPECT_NE(refusal(budget, {0}).find("by its word 0 (in a READ of 16777215"), std::string::npos);

  FrameBudget steps;
  EXPECT_EQ(steps.weigh(std::vector<std::uint32_t>{run(0xFFFFFF)}, 1).steps, 0u);
  const std::vector<std::uint32_t> plates(kMaxStepsPerFrame, 0);
  for (int frame = 0; frame < 3; ++frame) {
    EXPECT_EQ(steps.weigh(plates, 2 + frame).steps, kMaxStepsPerFrame);
  }
}

TEST(FrameBudget, AWordThatIsNoCommandIsAProtocolError) {
  FrameBudget budget;
  try {
    budget.weigh(std::vector<std::uint32_t>{0xE0000000u}, 1);
    FAIL() << "accepted";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kProtocol) << e.what();
  }
}

// The host's cut: every frame it makes passes the server's check, and together they are the
// words given, in order.
TEST(FrameBudget, TheHostCutsAnyStreamIntoFramesTheServerAccepts) {
  std::vector<std::uint32_t> words;
  words.push_back(run(10000));
  words.resize(1 + 10000, 0);
  for (int i = 0; i < 40; ++i) words.insert(words.end(), {read(frame::kRegionEdge, 65536), 0});
  words.push_back(status());
  FrameBudget host, server;
  std::size_t pos = 0;
  int frames = 0;
  while (pos < words.size()) {
    FrameCost cost;
    const std::size_t n = host.take_frame(std::span(words).subspan(pos), 262143, cost);
    ASSERT_GE(n, 1u);
    const FrameCost weighed = server.weigh(std::span(words).subspan(pos, n), 1 + frames);
    EXPECT_EQ(weighed.words, cost.words);
    EXPECT_EQ(weighed.answer_words, cost.answer_words);
    EXPECT_EQ(weighed.steps, cost.steps);
    pos += n;
    ++frames;
  }
  EXPECT_EQ(pos, words.size());
  // 10,000 steps take 3 frames (4,096 a frame), the 40 reads of 262,144 words 10 more (4 a
  // frame; 3 fit beside the last steps).
  EXPECT_EQ(frames, 3 + 10);
}

TEST(FrameBudget, AReadBeyondTheLimitStillGoesOutAloneForTheServerToRefuse) {
  FrameBudget host;
  const std::vector<std::uint32_t> words = {status(), read(frame::kRegionMaterial, 0xFFFFFF), 0,
                                            status()};
  FrameCost cost;
  EXPECT_EQ(host.take_frame(words, 1000, cost), 2u);  // STATUS and the READ's header
  EXPECT_EQ(host.take_frame(std::span(words).subspan(2), 1000, cost), 1u);  // its index alone
  EXPECT_EQ(cost.answer_words, 117440505u);
}

}  // namespace
}  // namespace rheo::link
