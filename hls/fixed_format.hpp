// The one place where the core's word lengths, binary points, coefficient encoding,
// status bits and the reciprocal-square-root seed table are defined. The bit-true model
// (hls/), the host conversion (host/driver/) and the RTL package rtl/rheo_consts_pkg.sv
// all take their numbers from here; rtl/rheo_consts_pkg.sv is generated from this header
// by `rheo_gen_rtl_pkg` and a test checks that the checked-in copy is up to date.
//
// Units (host-side constant folding, design.md §4): lengths are in a length unit Lu
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
template <int WidthV, int FracXV, int FracPV, int FracFV, Rounding RoundingV>
struct Format {
  static constexpr int kWidth = WidthV;
  static constexpr int kFracX = FracXV;
  static constexpr int kFracP = FracPV;
  static constexpr int kFracF = FracFV;
  static constexpr Rounding kRounding = RoundingV;
  static_assert(kWidth >= 16 && kWidth <= 48, "products must fit in 128 bits");
  static_assert(kFracP <= kWidth - 1 && kFracX < kFracP, "p must be finer than x");
};

// The hardware format (what the RTL implements): 32-bit words, x in Q5.27 (|x| < 16 Lu),
// p in Q1.31 (|p| < 1 Lu per step), forces in Q12.20 (|F| < 2048 Fu).
using HardwareFormat = Format<32, 27, 31, 20, Rounding::kNearest>;
// Exploration formats for `rheo fixed`: the same integer parts, 8 bits narrower/wider.
using NarrowFormat = Format<24, 19, 23, 12, Rounding::kNearest>;
using WideFormat = Format<40, 35, 39, 28, Rounding::kNearest>;
using HardwareTruncFormat = Format<32, 27, 31, 20, Rounding::kTruncate>;

// Unit vector u = r / l: Q2.30 in 32 bits, independent of the state format.
inline constexpr int kFracU = 30;

// Coefficients: value = mantissa * 2^-shift, an 18-bit signed mantissa (one MULT18X18
// operand) and a shift in [-16, 47], packed in one 24-bit word as
// {shift + kCoefShiftBias (6 bits), mantissa (18 bits)}.
inline constexpr int kCoefMantBits = 18;
inline constexpr int kCoefShiftBits = 6;
inline constexpr int kCoefShiftBias = 16;

// Reciprocal square root: l2 is normalised to m = M / 2^30 in [1, 4), the seed comes
// from a ROM indexed by the top kRsqrtIndexBits of M (m in [i/32, (i+1)/32)), and
// kRsqrtIterations Newton-Raphson steps y <- y (3 - m y^2) / 2 refine it in Q2.30.
inline constexpr int kRsqrtIndexBits = 7;
inline constexpr int kRsqrtSeedBits = 18;  // seed in Q1.17
inline constexpr int kRsqrtIterations = 2;
inline constexpr int kRsqrtFrac = 30;

// Seed for ROM index i (valid for i in [32, 127]): 1/sqrt of the interval midpoint.
inline std::uint32_t rsqrt_seed(int index) {
  if (index < (1 << (kRsqrtIndexBits - 2))) return 0;  // never addressed: m >= 1
  const double mid = (index + 0.5) / (1 << (kRsqrtIndexBits - 2));
  return static_cast<std::uint32_t>(std::lround(std::ldexp(1.0 / std::sqrt(mid), 17)));
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

// Pipeline drains of the core (rtl/rheo_core.sv), part of the cycles-per-step formula,
// counted from the clock after the last issue until the last write has landed:
// edge pass: particle read, TEM stages, accumulator read, sum, accumulator write;
// MPM pass: particle and sum read, sum register, MPM stages (the last output's plate
// force is taken and its write lands in the last clock).
// The module latencies (valid_i to valid_o of rtl/rheo_tem.sv and rtl/rheo_mpm.sv) are
// defined here so that the core's drains follow when a module's pipeline changes.
inline constexpr int kTemLatency = 18;
inline constexpr int kMpmLatency = 8;
inline constexpr int kTemDrainCycles = kTemLatency + 4;
inline constexpr int kMpmDrainCycles = kMpmLatency + 2;

// Accumulator widths: particle force sums and the plate force keep guard bits and
// saturate only when they are narrowed to a word (so the sums do not depend on the order
// in which lanes deliver them). The host keeps every particle's degree below 2^8.
inline constexpr int kForceAccGuardBits = 8;
inline constexpr int kPlateAccGuardBits = 16;

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
};

}  // namespace rheo::hls
