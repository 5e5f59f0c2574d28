#include "host/driver/link/crc32.hpp"

#include <gtest/gtest.h>

#include <string_view>

namespace rheo::link {
namespace {

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

TEST(Crc32, MatchesTheStandardCheckValueForTheDigitsOneToNine) {
  // The published check value of CRC-32/ISO-HDLC (zlib, Ethernet, PNG).
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926u);
}

TEST(Crc32, OfNothingIsZero) { EXPECT_EQ(crc32({}), 0u); }

TEST(Crc32, SplitUpdatesEqualOneUpdateOverTheConcatenation) {
  const std::string_view text = "The quick brown fox jumps over the lazy dog";
  EXPECT_EQ(crc32(bytes_of(text)), 0x414FA339u);  // a second published value
  for (std::size_t cut = 0; cut <= text.size(); ++cut) {
    const std::uint32_t state = crc32_update(kCrc32Init, bytes_of(text.substr(0, cut)));
    EXPECT_EQ(crc32_finish(crc32_update(state, bytes_of(text.substr(cut)))), 0x414FA339u)
        << "cut at " << cut;
  }
}

TEST(Crc32, ChangesWhenAnySingleBitFlips) {
  std::string text = "rheological object";
  const std::uint32_t clean = crc32(bytes_of(text));
  for (std::size_t i = 0; i < text.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::string flipped = text;
      flipped[i] = static_cast<char>(flipped[i] ^ (1 << bit));
      EXPECT_NE(crc32(bytes_of(flipped)), clean) << "byte " << i << " bit " << bit;
    }
  }
}

}  // namespace
}  // namespace rheo::link
