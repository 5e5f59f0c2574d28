// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, initial value and final XOR
// 0xFFFFFFFF): the checksum of a link frame. Same parameters as zlib, Ethernet and PNG, so a
// board's hardware CRC block or a capture tool can check our frames without a custom table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace rheo::link {

// The running register, so a frame's header and payload can be checksummed without copying
// them into one buffer: crc32_finish(crc32_update(crc32_update(kCrc32Init, a), b)).
inline constexpr std::uint32_t kCrc32Init = 0xFFFFFFFFu;
std::uint32_t crc32_update(std::uint32_t state, std::span<const std::uint8_t> bytes);
inline constexpr std::uint32_t crc32_finish(std::uint32_t state) { return state ^ 0xFFFFFFFFu; }

inline std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return crc32_finish(crc32_update(kCrc32Init, bytes));
}

}  // namespace rheo::link
