// The core's stream format: the words the host sends on s_axis and receives on m_axis.
// Shared by the host driver (both in-process devices), the RTL testbench and, through the
// generated package rtl/rheo_consts_pkg.sv, the RTL command decoder. Framing only: a
// transport (in-process call, socket, board link) carries these words unchanged.
//
// Every command starts with a header word  [31:29] opcode  [28:24] region  [23:0] count.
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
  kRegionEdge = 3,            // edge slot: packed ends (see kEdgeValid), L, d, material
  kRegionMaterial = 4,        // alpha, beta, kt, ct, a_min, a_max (packed), flags
  kRegionEdgeLength = 5,      // d only (read back the Voigt lengths), per edge slot
  // Parallel Maxwell arms, one pair of regions per arm j (arm j of a core built with
  // MaxwellArms = K > j; other cores flag a bad command):
  //   kRegionMaterialArm + 2 j: gamma_j, k2t_j (packed): the arm's decay and force coefficients
  //   kRegionEdgeArm + 2 j:     m_j: the arm spring's extension (X format), per edge slot
  kRegionMaterialArm = 6,
  kRegionEdgeArm = 7,
  // Force-dependent series damper (a core built with SeriesDamper = 1; others flag a bad
  // command): d_lo, d_span, zk, s_base, s_c2, ka (packed), see hls::MaterialCoefs.
  kRegionMaterialDamper = 22,
  // Strain hardening (a core built with StrainHardening = 1; others flag a bad command):
  // hk, s_k, ct_h (packed), see hls::MaterialCoefs.
  kRegionMaterialHardening = 23,
  // The sweep core (rtl/rheo_sweep_core.sv, hls/sweep_format.hpp; rheo_core refuses these):
  //   kRegionSweepParticle: the static word of a particle (global index): out-mask, mass
  //                         class, fixed, plate, has an edge into it
  //   kRegionSweepEdge:     d and the tag {first, class} of sweep slot lane << 17 | n (the
  //                         device read in the next step; kRegionEdgeLength reads d alone)
  //   kRegionSweepLane:     a lane's slab first, count, ghost count, start delay
  //   kRegionSweepOffset:   index offset k (0: unused)
  //   kRegionSweepClass:    edge class c: L (X format), material index
  //   kRegionSweepMass:     mass class: minv (packed)
  kRegionSweepParticle = 24,
  kRegionSweepEdge = 25,
  kRegionSweepLane = 26,
  kRegionSweepOffset = 27,
  kRegionSweepClass = 28,
  kRegionSweepMass = 29,
  // The tool unit (a core built with ToolContact = 1; others flag a bad command):
  //   kRegionTool:          the tool's registers, one word per entry (see ToolRegister);
  //                         written before each step, read back as the core holds them
  //   kRegionToolReaction:  entries 0..2: the reaction force on the tool (x, y, z, F format)
  //                         of the last step: minus the sum of the tool's forces on the
  //                         particles; writes are ignored
  kRegionTool = 30,
  kRegionToolReaction = 31,
  kNumRegions = 32,  // the base regions, kMaxArms arms, the damper, hardening, the sweep
                     // core's, the tool unit's
};

// Parallel Maxwell arms a core can carry: one region pair each, in the header's region field.
// Eight: the relaxation spectrum of the diagnosis (sim/relaxation_spectrum.cpp) has eight.
inline constexpr int kMaxArms = 8;
// Regions a core without Maxwell arms accepts.
inline constexpr std::uint32_t kNumBaseRegions = kRegionMaterialArm;
static_assert(kRegionMaterialDamper == kNumBaseRegions + 2 * kMaxArms);
static_assert(kNumRegions == kRegionToolReaction + 1);
// Packed coefficients of a damper region entry.
inline constexpr std::uint32_t kDamperCoefs = 6;
// Packed coefficients of a hardening region entry.
inline constexpr std::uint32_t kHardeningCoefs = 3;

inline constexpr Region material_arm_region(int arm) {
  return Region(kRegionMaterialArm + 2 * arm);
}
inline constexpr Region edge_arm_region(int arm) { return Region(kRegionEdgeArm + 2 * arm); }
// The arm a region belongs to (-1 for a base region).
inline constexpr int arm_of_region(std::uint32_t region) {
  return region >= kNumBaseRegions && region < kRegionMaterialDamper
             ? int(region - kNumBaseRegions) / 2
             : -1;
}
inline constexpr bool is_material_arm_region(std::uint32_t region) {
  return arm_of_region(region) >= 0 && (region - kRegionMaterialArm) % 2 == 0;
}
inline constexpr bool is_edge_arm_region(std::uint32_t region) {
  return arm_of_region(region) >= 0 && (region - kRegionEdgeArm) % 2 == 0;
}

inline constexpr std::uint32_t kWordsPerEntry[kNumRegions] = {1, 6, 5, 4, 7, 1, 2, 1, 2, 1, 2,
                                                              1, 2, 1, 2, 1, 2, 1, 2, 1, 2, 1,
                                                              kDamperCoefs, kHardeningCoefs,
                                                              1, 2, 4, 1, 2, 1, 1, 1};
// The words of a sweep-core lane entry (kRegionSweepLane) and edge class entry.
enum SweepLaneWord : std::uint32_t {
  kSweepLaneFirst = 0,
  kSweepLaneCount = 1,
  kSweepLaneGhost = 2,
  kSweepLaneDelay = 3,
};

enum GlobalRegister : std::uint32_t {
  kGlobalNumParticles = 0,
  kGlobalEdgeRows = 1,  // rows of the edge schedule (each row has one slot per lane)
  kGlobalGravityX = 2,  // P format, displacement per step^2
  kGlobalGravityY = 3,
  kGlobalGravityZ = 4,
  kGlobalControl = 5,  // kControl* bits; a write also forgets which particles the plate held
  kNumGlobals = 6,     // every core's
  // The sweep core's only: the clocks from one step's plate word to the next step's, when a
  // command runs several steps and the next word is there (0: each step after the last
  // one's force; host/driver/sweep_overlap.hpp computes it from the image).
  kGlobalSweepPeriod = 6,
};

// The tool unit's registers (region kRegionTool, hls::ToolRegs): the tool's kind
// (hls::ToolKind, bits [1:0]), its position now (X format), its displacement over the step
// (P format), its unit normal or axis (Q1.16 operands, sign-extended from bit 17), the reach
// (X format: eps, or radius + eps), half the cylinder's length (X format), the penalty
// coefficients kt and ct, the friction coefficient mu and a cylinder's surface displacement
// over the step dq R in P-format LSBs (spin) (coefficients packed).
enum ToolRegister : std::uint32_t {
  kToolKind = 0,
  kToolCx = 1, kToolCy = 2, kToolCz = 3,
  kToolDcx = 4, kToolDcy = 5, kToolDcz = 6,
  kToolAx = 7, kToolAy = 8, kToolAz = 9,
  kToolReach = 10,
  kToolHalfLength = 11,
  kToolKt = 12,
  kToolCt = 13,
  kToolMu = 14,
  kToolSpin = 15,
  kNumToolRegisters = 16,
};
inline constexpr std::uint32_t kToolReactionWords = 3;

inline constexpr std::uint32_t kControlFloor = 1u << 0;
inline constexpr std::uint32_t kControlPlate = 1u << 1;
// The plate keeps a particle it held in the previous step while the particle pushes against
// it (rheo::PlateContact::kHoldWhilePushing); without it the plate holds a particle only
// when its update would pass the plate (kPenetration).
inline constexpr std::uint32_t kControlPlateHold = 1u << 2;
inline constexpr std::uint32_t kStatusWords = 4;
// Status word 3: the core's lanes [7:0]; this bit marks the sweep core (rtl/rheo_sweep_core.sv).
inline constexpr std::uint32_t kStatusLanesMask = 0xFFu;
inline constexpr std::uint32_t kStatusLanesSweep = 1u << 8;
inline constexpr std::uint32_t kStatusClear = 1u << 0;

// Particles and edges are partitioned over the lanes: particle i lives in bank i % lanes
// at local address i / lanes, edge slot t (region index) belongs to lane t % lanes, row
// t / lanes. A slot's first word packs its two particles: the start particle's local
// address [11:0] (its bank is the slot's lane), the end particle's local address [23:12]
// and bank [27:24], and valid [31] (0: a bubble, nothing is computed in that slot).
inline constexpr int kEdgeLocalBits = 12;
inline constexpr int kEdgeEndLocalShift = 12;
inline constexpr int kEdgeEndBankShift = 24;
inline constexpr int kEdgeBankBits = 4;
inline constexpr int kEdgeValidBit = 31;
inline constexpr std::uint32_t kEdgeValid = 1u << kEdgeValidBit;
// A volume element's halves (hls::EdgeEntry): bit 30 marks an element slot, bit 29 its
// second half. The first half's L and d words hold V6_0 (low 32 bits in L), the second
// half's L the packed coefficient.
inline constexpr int kEdgeElementBit = 30;
inline constexpr int kEdgeSecondBit = 29;
inline constexpr std::uint32_t kEdgeElement = 1u << kEdgeElementBit;
inline constexpr std::uint32_t kEdgeSecond = 1u << kEdgeSecondBit;
static_assert(kEdgeEndBankShift + kEdgeBankBits <= kEdgeSecondBit);

// Packed coefficient: mantissa [17:0] (two's complement), shift [23:18].
inline constexpr int kCoefShiftPos = 18;

// Header word fields (shift = lowest bit). The index word that follows a WRITE or READ
// header and the count-like global registers (kGlobalNumParticles, kGlobalEdgeRows) use
// the same kCountBits low bits, so one counter width serves every index and count.
inline constexpr int kHeaderOpcodeShift = 29;
inline constexpr int kHeaderOpcodeBits = 3;
inline constexpr int kHeaderRegionShift = 24;
inline constexpr int kHeaderRegionBits = 5;
inline constexpr int kHeaderCountShift = 0;
inline constexpr int kCountBits = 24;
inline constexpr std::uint32_t kCountMask = (1u << kCountBits) - 1;
// Words of the longest entry (kRegionMaterial): the width of a word-within-entry counter.
inline constexpr std::uint32_t kMaxWordsPerEntry = 7;
static_assert(kHeaderCountShift + kCountBits <= kHeaderRegionShift &&
              kHeaderRegionShift + kHeaderRegionBits <= kHeaderOpcodeShift &&
              kHeaderOpcodeShift + kHeaderOpcodeBits <= 32);
static_assert(kNumRegions <= (1u << kHeaderRegionBits));
static_assert(kOpStatus < (1u << kHeaderOpcodeBits));
static_assert(kMaxWordsPerEntry == kWordsPerEntry[kRegionMaterial]);

inline constexpr std::uint32_t header(Opcode op, Region region, std::uint32_t count) {
  return (std::uint32_t(op) << kHeaderOpcodeShift) |
         (std::uint32_t(region) << kHeaderRegionShift) |
         ((count & kCountMask) << kHeaderCountShift);
}
inline constexpr Opcode header_opcode(std::uint32_t w) { return Opcode(w >> kHeaderOpcodeShift); }
inline constexpr std::uint32_t header_region(std::uint32_t w) {
  return (w >> kHeaderRegionShift) & ((1u << kHeaderRegionBits) - 1);
}
inline constexpr std::uint32_t header_count(std::uint32_t w) {
  return (w >> kHeaderCountShift) & kCountMask;
}

}  // namespace rheo::frame
