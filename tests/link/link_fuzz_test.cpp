// Seeded fuzz loops over the frame parser: random garbage, and valid streams with random
// corruption, truncation and chunking. The parser must never crash, never accept a frame that
// was not sent, and never let a damaged stream pass without an error.
#include <gtest/gtest.h>

#include <random>

#include "host/driver/link/link_frame.hpp"

namespace rheo::link {
namespace {

// Enough cases to hit every header field and chunking pattern many times, few enough to stay
// well under a second with the sanitizers on.
constexpr int kFuzzCases = 3000;
constexpr std::uint32_t kFuzzSeed = 20031;
// A small maximum so corrupted lengths are often "oversized" and often merely "too long".
constexpr std::uint32_t kFuzzMaxPayload = 4096;

struct Sent {
  FrameType type;
  std::vector<std::uint8_t> payload;
};

struct Outcome {
  std::vector<Frame> frames;
  bool error = false;
};

// Feeds `bytes` in random chunks, drains after each, and finishes the stream.
Outcome parse_chunked(const std::vector<std::uint8_t>& bytes, std::mt19937& rng) {
  FrameParser parser("fuzz", kFuzzMaxPayload);
  Outcome out;
  try {
    std::size_t pos = 0;
    while (pos < bytes.size()) {
      const std::size_t n =
          std::min<std::size_t>(bytes.size() - pos, 1 + rng() % (rng() % 2 ? 7 : 300));
      parser.feed(std::span(bytes.data() + pos, n));
      pos += n;
      while (auto f = parser.next()) out.frames.push_back(std::move(*f));
    }
    parser.finish("end of fuzz input");
  } catch (const LinkError&) {
    out.error = true;
  }
  return out;
}

std::vector<Sent> random_frames(std::mt19937& rng, std::vector<std::uint8_t>* stream) {
  std::vector<Sent> sent(1 + rng() % 6);
  for (std::uint32_t seq = 0; seq < sent.size(); ++seq) {
    Sent& s = sent[seq];
    s.type = static_cast<FrameType>(1 + rng() % 5);
    const std::size_t words = rng() % 3 == 0 ? 0 : rng() % 64;
    s.payload.resize(carries_words(s.type) ? 4 * words : rng() % 40);
    for (auto& b : s.payload) b = static_cast<std::uint8_t>(rng());
    const auto bytes = encode_frame(s.type, seq, s.payload);
    stream->insert(stream->end(), bytes.begin(), bytes.end());
  }
  return sent;
}

// Every accepted frame must be the frame sent at that position.
void expect_prefix_of_sent(const Outcome& out, const std::vector<Sent>& sent, int iteration) {
  ASSERT_LE(out.frames.size(), sent.size()) << "iteration " << iteration;
  for (std::size_t i = 0; i < out.frames.size(); ++i) {
    EXPECT_EQ(out.frames[i].type, sent[i].type) << "iteration " << iteration << " frame " << i;
    EXPECT_EQ(out.frames[i].payload, sent[i].payload)
        << "iteration " << iteration << " frame " << i;
  }
}

TEST(LinkFuzz, RandomBytesAreNeverAcceptedAsFrames) {
  std::mt19937 rng(kFuzzSeed);
  for (int it = 0; it < kFuzzCases; ++it) {
    std::vector<std::uint8_t> garbage(rng() % 200);
    for (auto& b : garbage) b = static_cast<std::uint8_t>(rng());
    const Outcome out = parse_chunked(garbage, rng);
    EXPECT_TRUE(out.frames.empty()) << "iteration " << it;
    EXPECT_EQ(out.error, !garbage.empty()) << "iteration " << it;
  }
}

TEST(LinkFuzz, GarbageBehindAValidMagicIsNeverAcceptedAsAFrame) {
  std::mt19937 rng(kFuzzSeed + 1);
  for (int it = 0; it < kFuzzCases; ++it) {
    // A plausible header (right magic, version, type, sequence) with random length and
    // random bytes where the payload and CRC should be.
    auto bytes = encode_frame(static_cast<FrameType>(1 + rng() % 5), 0, {});
    bytes.resize(kHeaderBytes);
    const std::uint32_t length = rng() % 2 ? 4 * (rng() % 16) : rng();
    for (int i = 0; i < 4; ++i) bytes[12 + i] = static_cast<std::uint8_t>(length >> (8 * i));
    const std::size_t tail = rng() % 100;
    for (std::size_t i = 0; i < tail; ++i) bytes.push_back(static_cast<std::uint8_t>(rng()));
    const Outcome out = parse_chunked(bytes, rng);
    EXPECT_TRUE(out.frames.empty()) << "iteration " << it;
    EXPECT_TRUE(out.error) << "iteration " << it;
  }
}

TEST(LinkFuzz, CorruptedStreamsYieldOnlySentFramesAndAlwaysAnError) {
  std::mt19937 rng(kFuzzSeed + 2);
  for (int it = 0; it < kFuzzCases; ++it) {
    std::vector<std::uint8_t> stream;
    const auto sent = random_frames(rng, &stream);
    const int mutations = 1 + static_cast<int>(rng() % 3);
    for (int m = 0; m < mutations; ++m) {
      std::uint8_t& b = stream[rng() % stream.size()];
      const std::uint8_t before = b;
      while (b == before) b = static_cast<std::uint8_t>(rng());
    }
    const Outcome out = parse_chunked(stream, rng);
    expect_prefix_of_sent(out, sent, it);
    EXPECT_TRUE(out.error) << "iteration " << it << ": corruption went unnoticed";
  }
}

TEST(LinkFuzz, TruncatedStreamsYieldOnlyWholeFramesAndReportTheCut) {
  std::mt19937 rng(kFuzzSeed + 3);
  for (int it = 0; it < kFuzzCases; ++it) {
    std::vector<std::uint8_t> stream;
    const auto sent = random_frames(rng, &stream);
    std::size_t boundary = 0;
    std::vector<std::size_t> ends;
    for (const Sent& s : sent) ends.push_back(boundary += kHeaderBytes + s.payload.size() + 4);
    stream.resize(rng() % stream.size());
    const Outcome out = parse_chunked(stream, rng);
    expect_prefix_of_sent(out, sent, it);
    const bool on_boundary =
        stream.empty() || std::find(ends.begin(), ends.end(), stream.size()) != ends.end();
    EXPECT_EQ(out.error, !on_boundary) << "iteration " << it;
  }
}

TEST(LinkFuzz, CleanStreamsInRandomChunksParseCompletely) {
  std::mt19937 rng(kFuzzSeed + 4);
  for (int it = 0; it < kFuzzCases; ++it) {
    std::vector<std::uint8_t> stream;
    const auto sent = random_frames(rng, &stream);
    const Outcome out = parse_chunked(stream, rng);
    EXPECT_FALSE(out.error) << "iteration " << it;
    EXPECT_EQ(out.frames.size(), sent.size()) << "iteration " << it;
    expect_prefix_of_sent(out, sent, it);
  }
}

}  // namespace
}  // namespace rheo::link
