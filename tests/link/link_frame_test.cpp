#include "host/driver/link/link_frame.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "host/driver/link/crc32.hpp"

namespace rheo::link {
namespace {

std::vector<std::uint8_t> concat(std::initializer_list<std::vector<std::uint8_t>> parts) {
  std::vector<std::uint8_t> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// Feeds everything and drains the parser; returns the frames and rethrows the first error.
std::vector<Frame> parse_all(FrameParser& parser, const std::vector<std::uint8_t>& bytes) {
  parser.feed(bytes);
  std::vector<Frame> frames;
  while (auto f = parser.next()) frames.push_back(std::move(*f));
  parser.finish("end of test stream");
  return frames;
}

LinkFault fault_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const LinkError& e) {
    return e.fault();
  }
  ADD_FAILURE() << "expected a LinkError";
  return LinkFault::kIo;
}

const std::vector<std::uint32_t> kWords = {0x20000003u, 0x00012345u, 0xFFFFFFFFu, 0u};

TEST(LinkFrame, HeaderLayoutIsLittleEndianMagicVersionTypeSequenceLength) {
  const auto bytes = encode_word_frame(FrameType::kCommand, 7, kWords);
  ASSERT_EQ(bytes.size(), kHeaderBytes + 4 * kWords.size() + kTrailerBytes);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "RHLK");
  EXPECT_EQ(bytes[4], kVersion);
  EXPECT_EQ(bytes[5], std::uint8_t(FrameType::kCommand));
  EXPECT_EQ(bytes[8], 7);
  EXPECT_EQ(bytes[12], 16);
  EXPECT_EQ(bytes[16], 0x03);  // first word, least significant byte first
  EXPECT_EQ(bytes[19], 0x20);
  const std::size_t body = bytes.size() - kTrailerBytes;
  const std::uint32_t crc = crc32(std::span(bytes.data(), body));
  EXPECT_EQ(bytes[body], crc & 0xFF);
  EXPECT_EQ(bytes[body + 3], crc >> 24);
}

TEST(LinkFrame, WordAndTextFramesRoundTripThroughTheParser) {
  FrameParser parser("test stream");
  const auto frames =
      parse_all(parser, concat({encode_word_frame(FrameType::kHello, 0, kWords),
                                encode_word_frame(FrameType::kResponse, 1, {}),
                                encode_text_frame(FrameType::kError, 2, "core overflow at step 12"),
                                encode_frame(FrameType::kShutdown, 3, {})}));
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0].type, FrameType::kHello);
  EXPECT_EQ(frames[0].words(), kWords);
  EXPECT_TRUE(frames[1].words().empty());
  EXPECT_EQ(frames[2].text(), "core overflow at step 12");
  EXPECT_EQ(frames[3].type, FrameType::kShutdown);
  EXPECT_EQ(frames[3].sequence, 3u);
  EXPECT_EQ(parser.expected_sequence(), 4u);
}

TEST(LinkFrame, ParserAssemblesFramesFedOneByteAtATime) {
  const auto bytes = concat({encode_word_frame(FrameType::kCommand, 0, kWords),
                             encode_word_frame(FrameType::kCommand, 1, kWords)});
  FrameParser parser("byte stream");
  std::vector<Frame> frames;
  for (std::uint8_t b : bytes) {
    parser.feed(std::span(&b, 1));
    while (auto f = parser.next()) frames.push_back(std::move(*f));
  }
  parser.finish("end");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].words(), kWords);
  EXPECT_FALSE(parser.mid_frame());
}

TEST(LinkFrame, WrongMagicIsReportedAsBadMagic) {
  auto bytes = encode_word_frame(FrameType::kCommand, 0, kWords);
  bytes[2] = 'X';
  FrameParser parser("s");
  EXPECT_EQ(fault_of([&] { parse_all(parser, bytes); }), LinkFault::kBadMagic);
}

TEST(LinkFrame, BadMagicIsReportedBeforeTheRestOfTheHeaderArrives) {
  FrameParser parser("s");
  const std::uint8_t garbage[4] = {'G', 'E', 'T', ' '};
  parser.feed(garbage);
  EXPECT_EQ(fault_of([&] { parser.next(); }), LinkFault::kBadMagic);
}

TEST(LinkFrame, UnknownVersionAndTypeAreReportedAsSuch) {
  auto wrong_version = encode_word_frame(FrameType::kCommand, 0, kWords);
  wrong_version[4] = 9;
  FrameParser a("s");
  EXPECT_EQ(fault_of([&] { parse_all(a, wrong_version); }), LinkFault::kBadVersion);
  auto wrong_type = encode_word_frame(FrameType::kCommand, 0, kWords);
  wrong_type[5] = 77;
  FrameParser b("s");
  EXPECT_EQ(fault_of([&] { parse_all(b, wrong_type); }), LinkFault::kBadType);
}

TEST(LinkFrame, AnyCorruptedPayloadOrCrcByteIsReportedAsBadCrc) {
  const auto clean = encode_word_frame(FrameType::kResponse, 0, kWords);
  for (std::size_t i = 8; i < clean.size(); ++i) {
    if (i >= 12 && i < 16) continue;  // the length field: covered by the next test
    auto bytes = clean;
    bytes[i] ^= 0x10;
    FrameParser parser("s");
    EXPECT_EQ(fault_of([&] { parse_all(parser, bytes); }), LinkFault::kBadCrc) << "byte " << i;
  }
}

TEST(LinkFrame, CorruptedLengthFieldNeverYieldsAFrame) {
  const auto clean = encode_word_frame(FrameType::kResponse, 0, kWords);
  for (std::size_t i = 12; i < 16; ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      auto bytes = clean;
      bytes[i] ^= std::uint8_t(1u << bit);
      FrameParser parser("s");
      const LinkFault fault = fault_of([&] { parse_all(parser, bytes); });
      // Shorter: the CRC lands on payload bytes; longer: the stream ends first, or the
      // length is not whole words, or above the maximum.
      EXPECT_TRUE(fault == LinkFault::kBadCrc || fault == LinkFault::kTruncated ||
                  fault == LinkFault::kOversized)
          << "byte " << i << " bit " << bit << ": " << to_string(fault);
    }
  }
}

TEST(LinkFrame, LengthAboveTheMaximumIsReportedAsOversizedFromTheHeaderAlone) {
  auto bytes = encode_word_frame(FrameType::kCommand, 0, kWords);
  bytes.resize(kHeaderBytes);
  bytes[12] = 0;
  bytes[13] = 0;
  bytes[14] = 0x40;  // 4 MiB
  FrameParser parser("s");
  parser.feed(bytes);
  EXPECT_EQ(fault_of([&] { parser.next(); }), LinkFault::kOversized);
}

TEST(LinkFrame, AgreedSmallerMaximumIsEnforced) {
  FrameParser parser("s", 8);
  EXPECT_EQ(fault_of([&] { parse_all(parser, encode_word_frame(FrameType::kCommand, 0, kWords)); }),
            LinkFault::kOversized);
}

TEST(LinkFrame, WordFrameWithAPartialWordIsRejected) {
  const std::uint8_t three_bytes[3] = {1, 2, 3};
  FrameParser parser("s");
  EXPECT_EQ(fault_of([&] {
              parse_all(parser, encode_frame(FrameType::kCommand, 0, std::span(three_bytes)));
            }),
            LinkFault::kOversized);
}

TEST(LinkFrame, StreamEndingInsideAFrameIsReportedAsTruncated) {
  const auto frame = encode_word_frame(FrameType::kResponse, 0, kWords);
  for (std::size_t cut = 1; cut < frame.size(); ++cut) {
    FrameParser parser("s");
    parser.feed(std::span(frame.data(), cut));
    EXPECT_FALSE(parser.next().has_value());
    EXPECT_EQ(fault_of([&] { parser.finish("peer closed the connection"); }), LinkFault::kTruncated)
        << "cut at " << cut;
  }
}

TEST(LinkFrame, MissingOrRepeatedFrameIsReportedAsSequenceGap) {
  FrameParser skipped("s");
  EXPECT_EQ(fault_of([&] {
              parse_all(skipped, concat({encode_word_frame(FrameType::kResponse, 0, kWords),
                                         encode_word_frame(FrameType::kResponse, 2, kWords)}));
            }),
            LinkFault::kSequenceGap);
  FrameParser repeated("s");
  EXPECT_EQ(fault_of([&] {
              parse_all(repeated, concat({encode_word_frame(FrameType::kResponse, 0, kWords),
                                          encode_word_frame(FrameType::kResponse, 0, kWords)}));
            }),
            LinkFault::kSequenceGap);
}

TEST(LinkFrame, MessagesNameTheStreamTheFrameAndWhatWasExpected) {
  FrameParser parser("from cosim-server /tmp/r.sock");
  try {
    parse_all(parser, concat({encode_word_frame(FrameType::kResponse, 0, kWords),
                              encode_word_frame(FrameType::kResponse, 5, kWords)}));
    FAIL() << "no error";
  } catch (const LinkError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sequence gap"), std::string::npos) << what;
    EXPECT_NE(what.find("expected sequence number 1, got 5"), std::string::npos) << what;
    EXPECT_NE(what.find("/tmp/r.sock"), std::string::npos) << what;
    EXPECT_NE(what.find("frame 1 at byte 36"), std::string::npos) << what;
  }
}

TEST(LinkFrame, ParserKeepsReportingTheFirstErrorAfterwards) {
  FrameParser parser("s");
  auto bad = encode_word_frame(FrameType::kCommand, 0, kWords);
  bad[20] ^= 1;
  parser.feed(bad);
  EXPECT_EQ(fault_of([&] { parser.next(); }), LinkFault::kBadCrc);
  parser.feed(encode_word_frame(FrameType::kCommand, 0, kWords));
  EXPECT_EQ(fault_of([&] { parser.next(); }), LinkFault::kBadCrc);
}

}  // namespace
}  // namespace rheo::link
