// The core's stream format: the words the host sends on s_axis and receives on m_axis.
// Shared by the host driver (both in-process devices), the RTL testbench and, through the
// generated package rtl/rheo_consts_pkg.sv, the RTL command decoder. Framing only: a
// transport (in-process call, socket, board link) carries these words unchanged.
//
// Every command starts with a header word  [31:28] opcode  [27:24] region  [23:0] count.
//   kOpWrite  region, count entries: next word = first entry index, then count entries of
//             words_per_entry(region) words each.                        No response.
//   kOpRun    count = N steps: then N plate-height words (X format), one consumed at the
//             start of each step.          Response: N plate-force words (F format), tlast
//                                          on the last.
//   kOpRead   region, count entries: next word = first entry index.     Response: count
//             entries of words_per_entry(region) words, tlast on the last word.
//   kOpStatus count bit 0 = clear the sticky flags after reading.       Response:
//             kStatusWords words (flags, step counter, compute cycles, lanes), tlast last.
// Input tlast is not interpreted (the header gives the length).
#pragma once

#include <cstdint>

namespace rheo::frame {

enum Opcode : std::uint32_t { kOpWrite = 1, kOpRun = 2, kOpRead = 3, kOpStatus = 4 };

enum Region : std::uint32_t {
  kRegionGlobals = 0,         // 1 word per entry: see GlobalRegister
  kRegionParticleState = 1,   // x[3], p[3]
  kRegionParticleStatic = 2,  // x0[3], minv (packed coefficient), flags
  kRegionEdge = 3,            // s | e << 16, L, d, material
  kRegionMaterial = 4,        // alpha, beta, kt, ct, a_min, a_max (packed), flags
  kRegionGather = 5,          // packed gather entry
  kRegionEdgeLength = 6,      // d only (read back the Voigt lengths)
  // Parallel Maxwell arm (cores built with MaxwellArm = 1 only; others flag a bad command):
  kRegionMaterialArm = 7,  // gamma, k2t (packed): the arm's decay and force coefficients
  kRegionEdgeArm = 8,      // m: the arm spring's extension (X format), written and read back
  kNumRegions = 9,
};

inline constexpr std::uint32_t kWordsPerEntry[kNumRegions] = {1, 6, 5, 4, 7, 1, 1, 2, 1};
// Regions a core without the Maxwell arm accepts.
inline constexpr std::uint32_t kNumBaseRegions = kRegionMaterialArm;

enum GlobalRegister : std::uint32_t {
  kGlobalNumParticles = 0,
  kGlobalNumEdges = 1,
  kGlobalGatherRows = 2,  // rows of the gather table (each row has one entry per lane)
  kGlobalGravityX = 3,    // P format, displacement per step^2
  kGlobalGravityY = 4,
  kGlobalGravityZ = 5,
  kGlobalControl = 6,  // bit 0 floor enable, bit 1 plate enable
  kNumGlobals = 7,
};

inline constexpr std::uint32_t kControlFloor = 1u << 0;
inline constexpr std::uint32_t kControlPlate = 1u << 1;
inline constexpr std::uint32_t kStatusWords = 4;
inline constexpr std::uint32_t kStatusClear = 1u << 0;

// Packed gather entry: edge [15:0], particle [27:16], valid [28], negate [29], last [30].
inline constexpr int kGatherParticleShift = 16;
inline constexpr std::uint32_t kGatherValid = 1u << 28;
inline constexpr std::uint32_t kGatherNegate = 1u << 29;
inline constexpr std::uint32_t kGatherLast = 1u << 30;

// Packed coefficient: mantissa [17:0] (two's complement), shift [23:18].
inline constexpr int kCoefShiftPos = 18;

inline constexpr std::uint32_t header(Opcode op, Region region, std::uint32_t count) {
  return (std::uint32_t(op) << 28) | (std::uint32_t(region) << 24) | (count & 0xFFFFFFu);
}
inline constexpr Opcode header_opcode(std::uint32_t w) { return Opcode(w >> 28); }
inline constexpr std::uint32_t header_region(std::uint32_t w) { return (w >> 24) & 0xF; }
inline constexpr std::uint32_t header_count(std::uint32_t w) { return w & 0xFFFFFFu; }

}  // namespace rheo::frame
