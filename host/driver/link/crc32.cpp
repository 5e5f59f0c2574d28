#include "host/driver/link/crc32.hpp"

#include <array>

namespace rheo::link {
namespace {

constexpr std::uint32_t kReflectedPolynomial = 0xEDB88320u;

// One entry per byte value: the register after shifting that byte through it bit by bit.
constexpr std::array<std::uint32_t, 256> make_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t reg = byte;
    for (int bit = 0; bit < 8; ++bit)
      reg = (reg & 1u) ? (reg >> 1) ^ kReflectedPolynomial : reg >> 1;
    table[byte] = reg;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kTable = make_table();

}  // namespace

std::uint32_t crc32_update(std::uint32_t state, std::span<const std::uint8_t> bytes) {
  for (std::uint8_t b : bytes) state = kTable[(state ^ b) & 0xFFu] ^ (state >> 8);
  return state;
}

}  // namespace rheo::link
