// The one place where the core's word lengths, binary points, coefficient encoding,
// status bits and the reciprocal-square-root seed table are defined. The bit-true model
// (hls/), the host conversion (host/driver/) and the RTL package rtl/rheo_consts_pkg.sv
// all take their numbers from here; rtl/rheo_consts_pkg.sv is generated from this header
// by `rheo_gen_rtl_pkg` and a test checks that the checked-in copy is up to date.
//
// Units (host-side constant folding, docs/hardware.md): lengths are in a length unit Lu
// chosen per model (largest extent / 8), forces in a force unit Fu (largest Voigt
// stiffness * Lu), time in steps. Velocity is stored as displacement per step
// p = v*dt/Lu, so the mass-point update is p += F*(Fu dt^2/(m Lu)) + g dt^2/Lu, x += p.
#pragma once

#include <cmath>
#include <cstdint>

namespace rheo::hls {

using i128 = __int128;

enum class Rounding {
  kNearest,   // add half an LSB, then shift (round half up); what the RTL does
  kTruncate,  // shift only (floor); only for the truncation ablation
};

// A fixed-point format of the state words. Every word is Width bits two's complement.
//   X: positions, Voigt lengths, edge vectors, plate height   (FracX fractional bits)
//   P: displacement per step and its rates (ldot, ddot)         (FracP fractional bits)
//   F: forces and the plate force                               (FracF fractional bits)
// The integer parts are fixed by the unit choice: |x| < 2^(Width-1-FracX) Lu etc.
// OperandBits: width of every multiplier operand of the TEM. State words stay Width bits;
// before a product a word (or a vector, with one shared exponent) is block-normalised to an
// OperandBits-bit signed mantissa and a right shift, and the product is shifted back. 18 is
// one MULT18X18 per product; OperandBits = Width leaves the words whole (no narrowing).
template <int WidthV, int FracXV, int FracPV, int FracFV, Rounding RoundingV,
          int OperandBitsV = WidthV>
struct Format {
  static constexpr int kWidth = WidthV;
  static constexpr int kFracX = FracXV;
  static constexpr int kFracP = FracPV;
  static constexpr int kFracF = FracFV;
  static constexpr Rounding kRounding = RoundingV;
  static constexpr int kOperandBits = OperandBitsV;
  // Unit vector u = r / |r| as an operand: Q1.(OperandBits-2), so that u = +-1 (an edge
  // along an axis) is representable.
  static constexpr int kFracU = OperandBitsV - 2;
  // Volume preservation: an element's six-fold volume as a word with kFracV fractional bits
  // (Lu^3); 64 bits hold it for elements up to (16 Lu)^3 (the host checks each one).
  static constexpr int kFracV = 2 * FracXV < 46 ? 2 * FracXV : 46;
  static_assert(kWidth >= 16 && kWidth <= 48, "products must fit in 128 bits");
  static_assert(kFracP <= kWidth - 1 && kFracX < kFracP, "p must be finer than x");
  static_assert(kOperandBits >= 18 && kOperandBits <= kWidth,
                "operands are at least one MULT18X18 wide and at most a word");
};

// The hardware format (what the RTL implements): 32-bit words, x in Q5.27 (|x| < 16 Lu),
// p in Q1.31 (|p| < 1 Lu per step), forces in Q12.20 (|F| < 2048 Fu); 18-bit multiplier
// operands.
inline constexpr int kHardwareOperandBits = 18;
using HardwareFormat = Format<32, 27, 31, 20, Rounding::kNearest, kHardwareOperandBits>;
// Ablation: the hardware words with full-width (32-bit) multiplier operands, i.e. what the
// narrowing to 18 bits costs.
using HardwareFullOperandFormat = Format<32, 27, 31, 20, Rounding::kNearest>;
// Exploration formats for `rheo fixed`: the same integer parts, 8 bits narrower/wider,
// full-width operands (so that the sweep measures word resolution alone).
using NarrowFormat = Format<24, 19, 23, 12, Rounding::kNearest>;
using WideFormat = Format<40, 35, 39, 28, Rounding::kNearest>;
using HardwareTruncFormat = Format<32, 27, 31, 20, Rounding::kTruncate, kHardwareOperandBits>;

// Coefficients: value = mantissa * 2^-shift, an 18-bit signed mantissa (one MULT18X18
// operand) and a shift in [-16, 47], packed in one 24-bit word as
// {shift + kCoefShiftBias (6 bits), mantissa (18 bits)}.
inline constexpr int kCoefMantBits = 18;
inline constexpr int kCoefShiftBits = 6;
inline constexpr int kCoefShiftBias = 16;

// Reciprocal square root of the normalised squared length l2n (an exact sum of squares of
// OperandBits-bit mantissas): l2n = m 2^(2k + parity) with m in [1, 2) rounded to an
// operand (Q1.(B-2), B = OperandBits). A seed ROM indexed by {parity, the top
// kRsqrtIndexBits - 1 fraction bits of m} gives y0 ~ 1/sqrt(m 2^parity) in Q0.17
// (relative error <= 2^-11), and Newton-Raphson steps y <- y + y (1 - m 2^parity y^2) / 2
// refine it in Q0.(B-1): one step for 18-bit operands (1.5 e0^2 ~ 2^-19 below the operand
// rounding), more for wider operands.
inline constexpr int kRsqrtIndexBits = 10;
inline constexpr int kRsqrtSeedBits = 17;  // seed in Q0.17, unsigned (always < 1)
// The correction term eps = 1 - m 2^parity y^2 stays below 2^-8 in magnitude (seed error
// <= 2^-10 gives |eps| <= ~2^-9); it is an operand with kRsqrtEpsExtraFrac more fractional
// bits than y.
inline constexpr int kRsqrtEpsExtraFrac = 8;
constexpr int rsqrt_iterations(int operand_bits) {
  return operand_bits <= 19 ? 1 : (operand_bits <= 37 ? 2 : 3);
}

// Seed for ROM index i = {parity, f} (f: kRsqrtIndexBits - 1 bits): 1/sqrt of the interval
// midpoint of m 2^parity, m in [1 + f/512, 1 + (f+1)/512).
inline std::uint32_t rsqrt_seed(int index) {
  const int frac_bits = kRsqrtIndexBits - 1;
  const int parity = index >> frac_bits;
  const int f = index & ((1 << frac_bits) - 1);
  const double mid = (1.0 + (f + 0.5) / (1 << frac_bits)) * (1 << parity);
  return static_cast<std::uint32_t>(std::lround(std::ldexp(1.0 / std::sqrt(mid), kRsqrtSeedBits)));
}

// Force-dependent series damper (seed 000 §3.3; rheo::series_viscosity): per edge the
// damper's viscosity is c2 = c2_max q with q = 2^-z, where z = log2(c2_max / c2) grows
// linearly with the Voigt spring force between f1 and f2 (A e^(-B f) in base 2). The core
// computes q from z with a table of 2^-f, f in [0, 1), and linear interpolation, and the
// reciprocal of s = c / c_ref (c = c1 + c2 + k1 dt, c_ref its value at c2_max) with a seed
// table and one Newton-Raphson step (docs/hardware.md, "Force-dependent series damper").
inline constexpr int kDamperFracZ = 16;    // fractional bits of z
inline constexpr int kDamperMaxZInt = 63;  // integer part of z (6 bits)
inline constexpr int kDamperZBits = kDamperFracZ + 6;  // z: an unsigned word of its own
inline constexpr int kExp2IndexBits = 6;   // 2^-f table: 64 segments (65 entries)
inline constexpr int kExp2TableBits = 16;  // entries in Q1.16 (2^-0 = 1 is representable)
// Fractional bits of s. s <= 1 (q <= 1); the host keeps s >= 2^-kDamperMinSBits, so that s
// carries at least kDamperFracS - kDamperMinSBits significant bits.
inline constexpr int kDamperFracS = 34;
inline constexpr int kDamperMinSBits = 16;
inline constexpr int kDamperSBits = kDamperFracS + 3;  // s and its terms: signed words
inline constexpr int kRecipIndexBits = 8;  // reciprocal seed: 256 segments of m in [1, 2)
inline constexpr int kRecipSeedBits = 16;  // seed in Q1.16

// Strain hardening (rheo::evaluate_edge): the Voigt spring's stiffness is k1 g with
// g = 1 + h, h = H e^2 and e = (l - L) / L (the reference's l0 is L, the edge's length at
// construction; the host checks that they are equal). The core computes 1/L with the
// reciprocal above, h as an unsigned word of its own, and scales the edge's coefficients by
// g and h over s = c / c_ref, which grows with h (docs/hardware.md, "Strain hardening").
inline constexpr int kHardFracH = 28;  // fractional bits of h
inline constexpr int kHardHBits = 40;  // h < 2^12: beyond, clamped and flagged
// s with hardening: s = s_base + s_c2 q + s_k h < 2 + 2^12 (s_k <= 1), signed
inline constexpr int kHardSBits = kDamperFracS + 14;

// 2^-(i / 64) in Q1.16, i = 0..64 (the interpolation reads entries i and i + 1).
inline std::uint32_t exp2_table(int index) {
  return static_cast<std::uint32_t>(
      std::lround(std::ldexp(std::exp2(-double(index) / (1 << kExp2IndexBits)), kExp2TableBits)));
}

// Seed for m in [1 + i/256, 1 + (i+1)/256): 1/m at the interval midpoint, in Q1.16.
inline std::uint32_t recip_seed(int index) {
  const double mid = 1.0 + (index + 0.5) / (1 << kRecipIndexBits);
  return static_cast<std::uint32_t>(std::lround(std::ldexp(1.0 / mid, kRecipSeedBits)));
}

// Status word bits (sticky until read-and-clear).
enum StatusBit : std::uint32_t {
  kStatusTemSaturated = 1u << 0,    // a TEM result saturated
  kStatusMpmSaturated = 1u << 1,    // an MPM result (force sum, p, x) saturated
  kStatusDegenerateEdge = 1u << 2,  // an edge of zero length (no direction)
  kStatusPlateSaturated = 1u << 3,  // the plate force word saturated
  kStatusBadCommand = 1u << 4,      // unknown opcode/region or index out of range
  // A row of the edge schedule has two end particles in one bank (or an end bank beyond
  // the lanes): the crossbar cannot serve it, forces of that row are not trustworthy.
  kStatusScheduleConflict = 1u << 5,
  // A volume element's force saturated (the element pass, volume preservation).
  kStatusVolumeSaturated = 1u << 6,
  // The tool's reaction force (the sum of its forces on the particles) saturated when
  // narrowed to its words (a core with the tool unit).
  kStatusToolReactionSaturated = 1u << 7,
};

// Material table entry flags.
enum MaterialFlag : std::uint32_t {
  kClampLowEnable = 1u << 0,   // d >= a_min * l
  kClampHighEnable = 1u << 1,  // d <= a_max * l
};

// Particle flags in the core (same values as rheo::ParticleFlag).
enum CoreParticleFlag : std::uint32_t { kCoreFixed = 1u << 0, kCorePlate = 1u << 1 };

// Static sizes of the core's memories (the HLS kernel's arrays and the RTL defaults).
inline constexpr int kMaxParticles = 4096;
inline constexpr int kMaxEdges = 65536;  // edge slots (rows * lanes, bubbles included)
inline constexpr int kMaxMaterials = 16;
inline constexpr int kMaxLanes = 4;
// The lane counts every command offers (--lanes) and every backend runs: rtl/CMakeLists.txt
// builds one Verilator model per count (a model per count keeps the lane count a parameter
// of the RTL, not a run-time setting), and the bit-true model and synthesis use the same set.
inline constexpr int kLaneCounts[] = {1, 2, 4};
inline constexpr int kDefaultLanes = 1;

// Pipeline drains of the core (rtl/rheo_core.sv), part of the cycles-per-step formula,
// counted from the clock after the last issue until the last write has landed:
// edge pass: particle read, TEM stages, accumulator read, sum, accumulator write;
// MPM pass: particle and sum read, sum register, saturated-sum register, MPM stages, then
// the plate force's lane-sum register and its accumulator addition (the word is narrowed
// from the accumulator in the last clock; the last particle's write has landed by then).
// The module latencies (valid_i to valid_o of rtl/rheo_tem.sv and rtl/rheo_mpm.sv) are
// defined here so that the core's drains follow when a module's pipeline changes.
inline constexpr int kTemLatency = 40;
inline constexpr int kMpmLatency = 8;
// rtl/rheo_tool.sv (hls/tool_contact.hpp): one particle's contact with a rigid tool.
inline constexpr int kToolLatency = 84;
inline constexpr int kTemDrainCycles = kTemLatency + 4;
// A TEM with strain hardening computes its coefficients from l, which it has at stage 21
// (rtl/rheo_harden.sv, 44 stages from stage 17): everything from the coefficient products
// on runs this much later, in the TEM's latency and in the edge pass's drain. With the
// series damper as well, the damper's state follows the hardened spring's extension, which
// needs h first (rheo_harden: 64 stages).
inline constexpr int kHardTemExtra = 32;
inline constexpr int kHardDamperTemExtra = 52;
constexpr int tem_latency(bool hardening, bool damper = false) {
  return kTemLatency + (hardening ? (damper ? kHardDamperTemExtra : kHardTemExtra) : 0);
}
constexpr int tem_drain_cycles(bool hardening, bool damper = false) {
  return tem_latency(hardening, damper) + 4;
}
static_assert(tem_drain_cycles(false) == kTemDrainCycles);
inline constexpr int kMpmDrainCycles = kMpmLatency + 5;

// Accumulator widths: particle force sums and the plate force keep guard bits and
// saturate only when they are narrowed to a word (so the sums do not depend on the order
// in which lanes deliver them). The host keeps every particle's degree below 2^8.
inline constexpr int kForceAccGuardBits = 8;
inline constexpr int kPlateAccGuardBits = 16;

// Volume (3-D) preservation (rheo::VolumePreservation) in the edge pass: a tetrahedron
// takes two consecutive slots of one lane (its vertices a, b in the first, c, d in the
// second; hls::volume_element). Its six-fold volume V6 = e_b . (e_c x e_d), e_k = x_k - x_a,
// is computed with kVolOperandBits-bit operands: two MULT18X18 columns per operand, so the
// hardware format's (Width + 1)-bit differences pass whole and the cross product is exact.
// V6 - V6_0 then cancels without the operand rounding of the edges' 18-bit products (which
// would leave V / V0 - 1 with an error near 1e-5). The gradients and the force products use
// the format's operands.
inline constexpr int kVolOperandBits = 35;

// Extra right shifts of the coefficient products, fixed by the formats:
//   ddot*dt = beta * ldot (P -> P)  - alpha * (d - L) (X -> P)
//   T = kt * (d - L) (X -> F) + ct * ldot (P -> F)
//   clamp bounds a * l (X -> X);  dp = minv * F (F -> P)
//   Maxwell arm: dm = ldot - gamma * m (X -> P);  T += k2t * m (X -> F)
template <class Fmt>
struct CoefShifts {
  static constexpr int kBeta = 0;
  static constexpr int kAlpha = Fmt::kFracX - Fmt::kFracP;
  static constexpr int kKt = Fmt::kFracX - Fmt::kFracF;
  static constexpr int kCt = Fmt::kFracP - Fmt::kFracF;
  static constexpr int kClamp = 0;
  static constexpr int kMinv = Fmt::kFracF - Fmt::kFracP;
  static constexpr int kGamma = Fmt::kFracX - Fmt::kFracP;
  static constexpr int kK2t = Fmt::kFracX - Fmt::kFracF;
  // Volume element: f = c * (V6 - V6_0) (V format) * g6 (two X-format factors) -> F.
  static constexpr int kVolume = Fmt::kFracV + 2 * Fmt::kFracX - Fmt::kFracF;
  // Tool friction: mu * F_n (F -> F); a cylinder's surface displacement over the step
  // spin * (a x u), u and a Q1.(B-2) operands and spin in P-format LSBs (-> P).
  static constexpr int kMu = 0;
  static constexpr int kSpin = Fmt::kFracU;
};

}  // namespace rheo::hls
