// Bit-true model of the core's datapath, written as an HLS kernel: static sizes, no
// allocation or recursion inside the kernel, loop pragmas as Vitis HLS takes them.
// It mirrors rtl/ operation for operation (formats, rounding points, rsqrt seed table and
// iterations; force sums are exact, so their order is free); tests/hw checks the two for
// exact equality.
//
// One step (equations of docs/model.md in folded units, see fixed_format.hpp):
//   TEM, per edge k (s -> e), one per clock:
//     r = x_e - x_s, dp = p_e - p_s, ds = d - L
//     y = rsqrt(r.r) (seed ROM + Newton-Raphson), l = |r| = r.r * y, u = r * y
//     (every product with Fmt::kOperandBits-bit operands: words and vectors are
//     block-normalised to a mantissa and a shared exponent before they are multiplied)
//     ldot = u . dp                          (length change per step)
//     dd = beta * ldot - alpha * ds          (Voigt length change per step)
//     T  = kt * ds + ct * ldot               (= k1 (d + dd - L) + c1 ddot, folded)
//     F_k = T * u;  d <- clamp(d + dd, a_min l, a_max l)
//   with Arms parallel Maxwell arms (template parameter Arms, RTL parameter MaxwellArms),
//   per edge and arm j a state m_j (the arm spring's extension, X format):
//     dm_j = ldot - gamma_j * m_j            (gamma_j = k_j dt / c_j)
//     T += sum_j k2t_j * m_j;  m_j <- m_j + dm_j   (k2t_j: the arm's spring in force units
//                                                    per length unit)
//     (the arms' products need only m_j, so the RTL computes them early in the pipeline)
//   with Damper (RTL parameter SeriesDamper), the force-dependent series damper: alpha, beta,
//   kt, ct scaled per edge by 1/s and q/s (damper_coefs; docs/hardware.md);
//   with Hardening, strain hardening: k1 (1 + hk e^2), e = (l - L) / L, the coefficients
//   scaled by g/s, q/s, g q/s and a fifth one, cth, on ldot (hardened_coefs; bit-true only
//   so far, no RTL core carries it)
//   MPM, per particle i, one per clock, after the edge pass has summed its edge forces
//   (exact wide sums, saturated once when narrowed):
//     f = sum of +F_k (i = s) and -F_k (i = e)
//     p += minv * f + g;  x += p
//     fixed: x = x0, p = 0
//     plate particle above the plate (z > plate_z), or on the plate in the previous step
//       (z_start = the previous plate height) and moving faster than it (p.z > lim,
//       lim = plate_z - z_start in P units): z = plate_z, p.z = min(p.z, lim),
//       plate force += f.z
//     with hold-while-pushing on, a plate particle the plate held in the previous step
//       (z_start = the previous plate height) that pushes (f.z > 0): z = plate_z,
//       p.z = plate_z - z_start, plate force += f.z
//     else free particle below the floor: z = 0, p.z = max(p.z, 0)
#pragma once

#include <algorithm>
#include <cstdint>

#include "hls/fixed_format.hpp"
#include "hls/frame_format.hpp"

namespace rheo::hls {

// ---- fixed-point primitives (the RTL's rheo_consts_pkg functions) ----------------------

// Shift right by s with the format's rounding (s <= 0 shifts left).
template <Rounding R>
inline i128 shift_round(i128 v, int s) {
  if (s <= 0) return v * (i128(1) << -s);
  if (R == Rounding::kNearest) v += i128(1) << (s - 1);
  return v >> s;  // arithmetic shift: floor
}

// Saturates to a Width-bit two's complement word, raising *flag when it clips.
inline std::int64_t saturate(i128 v, int width, std::uint32_t* status, std::uint32_t bit) {
  const i128 hi = (i128(1) << (width - 1)) - 1;
  const i128 lo = -(i128(1) << (width - 1));
  if (v > hi) {
    *status |= bit;
    return static_cast<std::int64_t>(hi);
  }
  if (v < lo) {
    *status |= bit;
    return static_cast<std::int64_t>(lo);
  }
  return static_cast<std::int64_t>(v);
}

// A coefficient: mantissa * 2^-shift.
struct Coef {
  std::int32_t mant = 0;   // 18-bit signed
  std::int32_t shift = 0;  // -16..47 (stored with kCoefShiftBias)
};

// a * coef, result shifted right by a further `extra` bits (the format change).
template <class Fmt>
inline std::int64_t mul_coef(std::int64_t a, const Coef& c, int extra, std::uint32_t* status,
                             std::uint32_t bit) {
  const i128 prod = i128(a) * c.mant;
  return saturate(shift_round<Fmt::kRounding>(prod, c.shift + extra), Fmt::kWidth, status, bit);
}

// Number of significant bits of a non-negative value (0 for 0).
inline int bit_length(i128 v) {
  int n = 0;
  while (v > 0 && n < 127) {
    v >>= 1;
    ++n;
  }
  return n;
}

// ---- block normalisation of multiplier operands -----------------------------------------

// n such that v in [-2^n, 2^n): leading-bit count of the two's complement word (the RTL
// ORs v XOR sign over the block and finds the leading one).
inline int signed_bit_length(i128 v) { return bit_length(v < 0 ? ~v : v); }

// Right shift that brings a block with signed_bit_length n into B-bit operands.
template <int B>
inline int operand_shift(int n) {
  return n > B - 1 ? n - (B - 1) : 0;
}

// v 2^-shift as a B-bit operand. Rounding to nearest can carry the largest positive value
// to 2^(B-1); it is held at 2^(B-1) - 1 (an error of one operand LSB, not a saturation).
template <int B, Rounding R>
inline std::int64_t to_operand(i128 v, int shift) {
  const i128 m = shift_round<R>(v, shift);
  const i128 hi = (i128(1) << (B - 1)) - 1;
  return static_cast<std::int64_t>(m > hi ? hi : m);
}

// A word or vector as B-bit operands with one shared exponent: value = mant * 2^shift.
template <int N>
struct Operands {
  std::int64_t mant[N];
  int shift;
};

template <int B, Rounding R, int N>
inline Operands<N> normalize(const std::int64_t (&v)[N]) {
  i128 bits = 0;
  for (int i = 0; i < N; ++i) bits |= v[i] < 0 ? ~i128(v[i]) : i128(v[i]);
  Operands<N> out;
  out.shift = operand_shift<B>(bit_length(bits));
  for (int i = 0; i < N; ++i) out.mant[i] = to_operand<B, R>(v[i], out.shift);
  return out;
}

template <int B, Rounding R>
inline Operands<1> normalize(std::int64_t v) {
  const std::int64_t block[1] = {v};
  return normalize<B, R, 1>(block);
}

// A product of two operands (up to 2B bits, wider than 64 for the wide sweep formats) as one
// B-bit operand: the same result as normalize on a word that held it.
template <int B, Rounding R>
inline Operands<1> normalize_product(i128 v) {
  Operands<1> out;
  out.shift = operand_shift<B>(signed_bit_length(v));
  out.mant[0] = to_operand<B, R>(v, out.shift);
  return out;
}

// word * coef, shifted right by a further `extra` bits (the format change), with the word
// narrowed to an operand first: the operand's exponent is added to the coefficient shift.
template <class Fmt>
inline std::int64_t mul_coef_operand(std::int64_t word, const Coef& c, int extra,
                                     std::uint32_t* status, std::uint32_t bit) {
  const Operands<1> a = normalize<Fmt::kOperandBits, Fmt::kRounding>(word);
  const i128 prod = i128(a.mant[0]) * c.mant;
  return saturate(shift_round<Fmt::kRounding>(prod, c.shift + extra - a.shift), Fmt::kWidth,
                  status, bit);
}

// ---- reciprocal square root -----------------------------------------------------------

struct RsqrtResult {
  std::int64_t mant;  // m in [1, 2) as a Q1.(B-2) operand
  std::int64_t y;     // ~ 1/sqrt(m 2^parity) as a Q0.(B-1) operand, in (1/2, 1)
  int parity;         // l2n = m 2^(2k + parity)
  int k;
  bool degenerate;    // l2n == 0: every output 0
};

// y = 1/sqrt(m 2^parity) for m = m_raw 2^-(B-2) in [1, 2). Shared by the l2 path and the
// accuracy test. Every product has B-bit operands.
template <int B, Rounding R>
inline std::int64_t rsqrt_mantissa(std::int64_t m_raw, int parity) {
  static_assert(B >= kRsqrtSeedBits + 1, "the seed is an operand");
  const int index = (parity << (kRsqrtIndexBits - 1)) |
                    static_cast<int>((m_raw >> (B - 1 - kRsqrtIndexBits)) &
                                     ((1 << (kRsqrtIndexBits - 1)) - 1));
  std::int64_t y = std::int64_t(rsqrt_seed(index)) << (B - 1 - kRsqrtSeedBits);
  const std::int64_t y_max = (std::int64_t(1) << (B - 1)) - 1;
  constexpr int kEpsFrac = B - 1 + kRsqrtEpsExtraFrac;  // fractional bits of the eps operand
#pragma HLS UNROLL
  for (int it = 0; it < rsqrt_iterations(B); ++it) {
    // m y in Q1.(B-2), then m y^2 exact in Q1.(2B-3)
    const std::int64_t my = static_cast<std::int64_t>(shift_round<R>(i128(m_raw) * y, B - 1));
    const i128 my2 = i128(my) * y;
    const i128 eps_wide = (i128(1) << (2 * B - 3)) - (my2 << parity);
    const std::int64_t eps = to_operand<B, R>(eps_wide, 2 * B - 3 - kEpsFrac);
    // y + y eps / 2: y eps has B - 1 + kEpsFrac fractional bits, one more for the half.
    const i128 corr = shift_round<R>(i128(y) * eps, kEpsFrac + 1);
    const i128 y_new = i128(y) + corr;
    y = static_cast<std::int64_t>(y_new > y_max ? y_max : y_new);
  }
  return y;
}

// Normalises the squared operand length l2n (exact, non-negative) to m 2^(2k + parity).
template <int B, Rounding R>
inline RsqrtResult rsqrt_l2(i128 l2n) {
  RsqrtResult res{0, 0, 0, 0, l2n == 0};
  if (res.degenerate) return res;
  const int n = bit_length(l2n);
  // l2n ~ m_raw 2^(n - (B-1)) = m 2^(n-1)
  res.mant = to_operand<B, R>(l2n, n - (B - 1));
  res.parity = (n - 1) & 1;
  res.k = (n - 1) >> 1;
  res.y = rsqrt_mantissa<B, R>(res.mant, res.parity);
  return res;
}

// ---- TEM ------------------------------------------------------------------------------

// Parallel Maxwell arms the kernel can carry (the frame format's arm regions).
inline constexpr int kMaxArms = frame::kMaxArms;

struct MaterialCoefs {
  Coef alpha, beta, kt, ct, a_min, a_max;
  std::uint32_t flags = 0;  // MaterialFlag
  // Maxwell arm j (read only by a kernel with more than j arms); an arm a material does
  // not use has zero coefficients: no force, and its extension only follows the length.
  Coef gamma[kMaxArms], k2t[kMaxArms];
  // Force-dependent series damper (read only by a kernel with Damper = true; region
  // MaterialDamper). alpha, beta, kt, ct above are then the coefficients at c2 = c2_max
  // (ct without the arms' k, which is ka), and per edge (damper_coefs):
  //   z = zk * clamp(|d - L| - d_lo, 0, d_span)       (kDamperFracZ fractional bits)
  //   q = 2^-z = c2 / c2_max,  s = s_base + s_c2 q = c / c_ref,
  //   alpha / s, beta q / s, kt q / s, ct q / s;  T += ka * ldot.
  Coef d_lo, d_span;  // |d - L| (a length) where c2 starts to fall, and the width of the fall
  Coef zk;            // z per X-format LSB of |d - L| - d_lo
  Coef s_base, s_c2;  // (c1 + k1 dt) / c_ref and c2_max / c_ref
  Coef ka;            // the arms' k (their springs' lead on ldot), F per P
  // Strain hardening (read only by a kernel with Hardening = true; region
  // MaterialHardening): per edge h = hk e^2, e = (l - L) / L, and (hardened_coefs)
  //   s = s_base + s_c2 q + s_k h (without the damper q = 1 and s_base + s_c2 = 1),
  //   alpha g / s, beta q / s, kt g q / s, ct q / s, and cth = ct_h h q / s on ldot.
  Coef hk;    // the hardening coefficient H (per strain squared)
  Coef s_k;   // k1 dt / c_ref: the stiffness's share of s
  Coef ct_h;  // k1 c2 / c_ref, F per P: the hardened stiffness's lead in T's ldot term
};

struct TemIn {
  std::int64_t xs[3], xe[3], ps[3], pe[3];
  std::int64_t d, L;
  std::int64_t m[kMaxArms] = {};  // Maxwell-arm extensions (X format)
};

struct TemOut {
  std::int64_t f[3];   // force on the start particle (F format); the end gets -f
  std::int64_t d;      // new Voigt length (X format)
  std::int64_t m[kMaxArms] = {};  // new Maxwell-arm extensions (X format; 0 beyond Arms)
};

// ---- force-dependent series damper -------------------------------------------------------

// A coefficient as a word with `frac` fractional bits (mant 2^(frac - shift), rounded).
template <Rounding R>
inline i128 coef_word(const Coef& c, int frac) {
  return shift_round<R>(i128(c.mant), c.shift - frac);
}

// The coefficients alpha, beta, kt, ct of this edge with the force-dependent series damper:
// the material's (at c2 = c2_max) times 1/s (alpha) or q/s (the others), with
//   q = 2^-z, z = zk * clamp(|ds| - d_lo, 0, d_span),  s = s_base + s_c2 q.
// q: the table of 2^-f at the top kExp2IndexBits fraction bits of z, interpolated linearly
// over the rest, times 2^-floor(z). 1/s: s normalised to m 2^(nb-1) with m in [1, 2), a seed
// 1/m from the top kRecipIndexBits fraction bits of m, one Newton-Raphson step
// y = y0 (2 - m y0). Every product has B-bit operands. A scaled coefficient keeps its
// 18-bit mantissa (q and y are at most 1) and takes the exponents of q and 1/s into its
// shift; a shift the packed format or the datapath cannot take is clamped and flagged
// (the host keeps every reachable shift in range).
struct DampedCoefs {
  Coef alpha, beta, kt, ct;
  Coef cth;  // with strain hardening: the hardened stiffness's share of the ldot term
};

// Shift limits of a damped coefficient: the packed field, and shift + extra >= 0 (the
// datapath never shifts a coefficient product left beyond the operand's exponent).
inline int damped_shift(int shift, int extra, std::uint32_t* status) {
  const int lo = extra > kCoefShiftBias ? -kCoefShiftBias : -extra;
  const int hi = (1 << kCoefShiftBits) - 1 - kCoefShiftBias;
  if (shift < lo) {
    *status |= kStatusTemSaturated;
    return lo;
  }
  if (shift > hi) {
    *status |= kStatusTemSaturated;
    return hi;
  }
  return shift;
}

// 2^-f for the kDamperFracZ fraction bits f of z, in Q1.(B-2) (in [1/2, 1]): the table at
// the top kExp2IndexBits bits, interpolated linearly over the rest.
template <int B, Rounding R>
inline std::int64_t exp2_neg_frac(std::int64_t z) {
  constexpr int kInterpBits = kDamperFracZ - kExp2IndexBits;
  const int idx = static_cast<int>((z >> kInterpBits) & ((1 << kExp2IndexBits) - 1));
  const std::int64_t t = z & ((std::int64_t(1) << kInterpBits) - 1);
  const std::int64_t e0 = std::int64_t(exp2_table(idx)) << (B - 2 - kExp2TableBits);
  const std::int64_t e1 = std::int64_t(exp2_table(idx + 1)) << (B - 2 - kExp2TableBits);
  return e0 - static_cast<std::int64_t>(shift_round<R>(i128(e0 - e1) * t, kInterpBits));
}

// 1/m for m = mr 2^-(B-2) in [1, 2), in Q1.(B-2) (at most 1): the seed at the top
// kRecipIndexBits fraction bits of m, then one Newton-Raphson step y0 (2 - m y0).
template <int B, Rounding R>
inline std::int64_t recip_mantissa(std::int64_t mr) {
  const int ridx =
      static_cast<int>((mr >> (B - 2 - kRecipIndexBits)) & ((1 << kRecipIndexBits) - 1));
  const std::int64_t y0 = std::int64_t(recip_seed(ridx)) << (B - 2 - kRecipSeedBits);
  const std::int64_t my = static_cast<std::int64_t>(shift_round<R>(i128(mr) * y0, B - 2));
  const std::int64_t e = (std::int64_t(1) << (B - 1)) - my;  // 2 - m y0, Q1.(B-2)
  const std::int64_t y = static_cast<std::int64_t>(shift_round<R>(i128(y0) * e, B - 2));
  const std::int64_t one = std::int64_t(1) << (B - 2);
  return y > one ? one : y;
}

// q = 2^-z of the damper for the spring's extension a = |d - L| (times g with strain
// hardening), a >= 0 and exact: qm in Q1.(B-2), in [1/2, 1], and q = qm 2^-(B-2) 2^-n.
struct DamperQ {
  std::int64_t qm;
  int n;
};

template <class Fmt>
inline DamperQ damper_q(i128 a, const MaterialCoefs& m, std::uint32_t* status) {
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  // a beyond d_lo, clamped to the span. d_lo and d_span as words are held quietly to
  // W + 2 bits (beyond, the clamp gives the same result as the exact value would), so the
  // excess is exact in W + 3 bits and is normalised as it is (never saturates).
  const auto quiet = [](i128 v) {
    const i128 hi = (i128(1) << (W + 1)) - 1;
    return v > hi ? hi : (v < -hi - 1 ? -hi - 1 : v);
  };
  i128 excess = a - quiet(coef_word<R>(m.d_lo, Fmt::kFracX));
  const i128 span = quiet(coef_word<R>(m.d_span, Fmt::kFracX));
  if (excess < 0) excess = 0;
  if (excess > span) excess = span;
  // z = zk * excess as an unsigned kDamperZBits-bit word (its own width, not a state word):
  // z < 0 (a negative zk, which the host never writes) counts as 0; z beyond the word
  // (q < 2^-kDamperMaxZInt, below every word's resolution) is clamped and flagged.
  const Operands<1> en = normalize<B, R>(static_cast<std::int64_t>(excess));
  const i128 z_wide = shift_round<R>(i128(en.mant[0]) * m.zk.mant, m.zk.shift - en.shift);
  constexpr std::int64_t kZMax = (std::int64_t(1) << kDamperZBits) - 1;
  std::int64_t zc = 0;
  if (z_wide > kZMax) {
    *status |= kStatusTemSaturated;
    zc = kZMax;
  } else if (z_wide > 0) {
    zc = static_cast<std::int64_t>(z_wide);
  }
  return {exp2_neg_frac<B, R>(zc), static_cast<int>(zc >> kDamperFracZ)};
}

// s_base + s_c2 q with kDamperFracS fractional bits, each term and the sum saturated to
// SBits (the host keeps s in range; wider words would only carry invalid tables).
template <class Fmt, int SBits>
inline i128 damper_s(const DamperQ& q, const MaterialCoefs& m, std::uint32_t* status) {
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  const std::uint32_t kFlag = kStatusTemSaturated;
  const std::int64_t s_term_base =
      saturate(coef_word<R>(m.s_base, kDamperFracS), SBits, status, kFlag);
  const std::int64_t s_term_q = saturate(
      shift_round<R>(i128(q.qm) * m.s_c2.mant, m.s_c2.shift + (B - 2) + q.n - kDamperFracS),
      SBits, status, kFlag);
  return saturate(i128(s_term_base) + s_term_q, SBits, status, kFlag);
}

// 1/s for s with kDamperFracS fractional bits: y in Q1.(B-2) (at most 1) and s's bit length
// nb, 1/s = y 2^-(B-2) 2^(kDamperFracS + 1 - nb). s <= 0 (which the host never lets happen)
// is flagged and counts as 1.
struct RecipS {
  std::int64_t y;
  int nb;
};

template <class Fmt>
inline RecipS recip_s(i128 s, std::uint32_t* status) {
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  if (s <= 0) {
    *status |= kStatusTemSaturated;
    return {std::int64_t(1) << (B - 2), kDamperFracS + 1};
  }
  const int nb = bit_length(s);
  // m in [1, 2) as Q1.(B-2); rounding up to 2 is held at the largest operand
  return {recip_mantissa<B, R>(to_operand<B, R>(s, nb - (B - 1))), nb};
}

template <class Fmt>
inline DampedCoefs damper_coefs(std::int64_t ds, const MaterialCoefs& m, std::uint32_t* status) {
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  using S = CoefShifts<Fmt>;
  const DamperQ q = damper_q<Fmt>(ds < 0 ? -i128(ds) : i128(ds), m, status);
  const RecipS rs = recip_s<Fmt>(damper_s<Fmt, kDamperSBits>(q, m, status), status);
  // c * f, f = fm 2^-(B-2) 2^-dshift with fm in [0, 2^(B-2)]: the mantissa cannot grow
  const auto scale = [&](const Coef& c, std::int64_t fm, int dshift) {
    Coef out;
    out.mant = static_cast<std::int32_t>(shift_round<R>(i128(c.mant) * fm, B - 2));
    out.shift = c.shift + dshift;
    return out;
  };
  const int rshift = rs.nb - kDamperFracS - 1;  // 1/s's exponent as a shift
  DampedCoefs out;
  out.alpha = scale(m.alpha, rs.y, rshift);
  out.beta = scale(scale(m.beta, q.qm, q.n), rs.y, rshift);
  out.kt = scale(scale(m.kt, q.qm, q.n), rs.y, rshift);
  out.ct = scale(scale(m.ct, q.qm, q.n), rs.y, rshift);
  out.alpha.shift = damped_shift(out.alpha.shift, S::kAlpha, status);
  out.beta.shift = damped_shift(out.beta.shift, S::kBeta, status);
  out.kt.shift = damped_shift(out.kt.shift, S::kKt, status);
  out.ct.shift = damped_shift(out.ct.shift, S::kCt, status);
  return out;
}

// ---- strain hardening -----------------------------------------------------------------

// A positive factor f = m 2^-(B-2) 2^e with m in [2^(B-3), 2^(B-2)] (f in [1/2, 1] 2^e), or
// m = 0 (f = 0).
struct Factor {
  std::int64_t m = 0;
  int e = 0;
};

// The factor of a word >= 0 with `frac` fractional bits.
template <int B, Rounding R>
inline Factor factor_of(i128 word, int frac) {
  if (word <= 0) return {};
  const int n = bit_length(word);
  return {static_cast<std::int64_t>(shift_round<R>(word, n - (B - 2))), n - frac};
}

// a b, renormalised by at most one bit (the product of the mantissas is in [1/4, 1]).
template <int B, Rounding R>
inline Factor factor_mul(const Factor& a, const Factor& b) {
  if (a.m == 0 || b.m == 0) return {};
  const i128 p = i128(a.m) * b.m;
  if (p < (i128(1) << (2 * B - 5)))
    return {static_cast<std::int64_t>(shift_round<R>(p, B - 3)), a.e + b.e - 1};
  return {static_cast<std::int64_t>(shift_round<R>(p, B - 2)), a.e + b.e};
}

// h = hk e^2 with e = (l - L) / L, as an unsigned word with kHardFracH fractional bits.
// 1/L: L normalised to m 2^(nl-1), m in [1, 2), and the reciprocal of the damper. e and e^2
// are rounded to B-bit operands. L <= 0 (the host never writes one) and h beyond its word
// are flagged (h is then 0 or its largest value).
template <class Fmt>
inline std::int64_t hardening_h(std::int64_t l, std::int64_t L, const Coef& hk,
                                std::uint32_t* status) {
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  constexpr std::int64_t kHMax = (std::int64_t(1) << kHardHBits) - 1;
  if (L <= 0) {
    *status |= kStatusTemSaturated;
    return 0;
  }
  const int nl = bit_length(L);
  const std::int64_t y_l = recip_mantissa<B, R>(to_operand<B, R>(L, nl - (B - 1)));
  const Operands<1> dn = normalize<B, R>(l - L);  // l, L: W-bit words
  // e = dn y_l 2^(dn.shift - (B-2) - (nl-1))
  const Operands<1> en = normalize_product<B, R>(i128(dn.mant[0]) * y_l);
  const int ee = en.shift + dn.shift - (B - 2) - (nl - 1);
  // e^2 = e2 2^(e2.shift + 2 ee); h = e2 hk with kHardFracH fractional bits
  const Operands<1> e2 = normalize_product<B, R>(i128(en.mant[0]) * en.mant[0]);
  // a right shift beyond 2B rounds every product (< 2^(2B-2)) to 0, a left shift beyond the
  // word overflows every non-zero one: the shift is held to that range
  const int sh = std::clamp(hk.shift - e2.shift - 2 * ee - kHardFracH, -kHardHBits, 2 * B);
  const i128 h = shift_round<R>(i128(e2.mant[0]) * hk.mant, sh);
  if (h <= 0) return 0;  // (a negative hk, which the host never writes, counts as 0)
  if (h > kHMax) {
    *status |= kStatusTemSaturated;
    return kHMax;
  }
  return static_cast<std::int64_t>(h);
}

// A scaled coefficient c f: its mantissa cannot grow (f's mantissa is at most 1). Its shift
// is held to the packed format: a coefficient too large for it is clamped and flagged; one
// too small gives up mantissa bits instead (cth falls to 0 with h, which is no error).
template <class Fmt>
inline Coef scaled_coef(const Coef& c, const Factor& f, int extra, std::uint32_t* status) {
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  const int lo = extra > kCoefShiftBias ? -kCoefShiftBias : -extra;
  const int hi = (1 << kCoefShiftBits) - 1 - kCoefShiftBias;
  Coef out;
  int shift = c.shift - f.e;
  if (f.m == 0 || c.mant == 0) return {0, hi};
  if (shift < lo) {
    *status |= kStatusTemSaturated;
    shift = lo;
  }
  // the product, rounded once, at shift <= hi
  const int drop = std::min(std::max(shift - hi, 0), 2 * B);
  out.mant = static_cast<std::int32_t>(shift_round<R>(i128(c.mant) * f.m, B - 2 + drop));
  out.shift = shift - drop;
  return out;
}

// The coefficients of this edge with strain hardening (and, with Damper, the force-dependent
// series damper, whose force is the hardened spring's: z follows g |d - L|):
//   g = 1 + h, q = 2^-z, s = s_base + s_c2 q + s_k h (1 + s_k h without the damper),
//   alpha g / s, beta q / s, kt g q / s, ct q / s, cth = ct_h h q / s.
// Each is the material's coefficient times one factor (g/s, q/s, g q/s, h q/s), each factor a
// product of normalised factors.
template <class Fmt, bool Damper>
inline DampedCoefs hardened_coefs(std::int64_t ds, std::int64_t l, std::int64_t L,
                                  const MaterialCoefs& m, std::uint32_t* status) {
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  using S = CoefShifts<Fmt>;
  const std::uint32_t kFlag = kStatusTemSaturated;
  const std::int64_t h = hardening_h<Fmt>(l, L, m.hk, status);
  const Factor fh = factor_of<B, R>(h, kHardFracH);
  const Factor fg = factor_of<B, R>(i128(h) + (i128(1) << kHardFracH), kHardFracH);
  Factor fq{std::int64_t(1) << (B - 2), 0};  // q = 1
  i128 s = i128(1) << kDamperFracS;          // s_base + s_c2 = 1 without the damper
  if constexpr (Damper) {
    // g |ds| = |ds| + h |ds|, the second term held quietly to W + 2 bits (the damper clamps
    // the excess to its span)
    const i128 abs_ds = ds < 0 ? -i128(ds) : i128(ds);
    const Operands<1> an = normalize<B, R>(static_cast<std::int64_t>(abs_ds));
    // h |ds| = fh.m an 2^(an.shift + fh.e - (B-2)), a word with FracX fractional bits
    const int hds_shift = std::clamp((B - 2) - fh.e - an.shift, -(W + 2), 2 * B);
    i128 h_ds = shift_round<R>(i128(fh.m) * an.mant[0], hds_shift);
    const i128 quiet_hi = (i128(1) << (W + 1)) - 1;
    if (h_ds > quiet_hi) h_ds = quiet_hi;
    const DamperQ q = damper_q<Fmt>(abs_ds + h_ds, m, status);
    fq = {q.qm, -q.n};
    s = damper_s<Fmt, kHardSBits>(q, m, status);
  }
  // + s_k h with kDamperFracS fractional bits (h = fh.m 2^-(B-2) 2^fh.e)
  const int sk_shift =
      std::clamp(m.s_k.shift + (B - 2) - fh.e - kDamperFracS, -kHardSBits, 2 * B);
  const std::int64_t s_term_h = saturate(shift_round<R>(i128(fh.m) * m.s_k.mant, sk_shift),
                                         kHardSBits, status, kFlag);
  const RecipS rs = recip_s<Fmt>(saturate(s + s_term_h, kHardSBits, status, kFlag), status);
  const Factor fy{rs.y, kDamperFracS + 1 - rs.nb};
  const Factor fqy = factor_mul<B, R>(fq, fy);
  DampedCoefs out;
  out.alpha = scaled_coef<Fmt>(m.alpha, factor_mul<B, R>(fg, fy), S::kAlpha, status);
  out.beta = scaled_coef<Fmt>(m.beta, fqy, S::kBeta, status);
  out.kt = scaled_coef<Fmt>(m.kt, factor_mul<B, R>(fg, fqy), S::kKt, status);
  out.ct = scaled_coef<Fmt>(m.ct, fqy, S::kCt, status);
  out.cth = scaled_coef<Fmt>(m.ct_h, factor_mul<B, R>(fh, fqy), S::kCt, status);
  return out;
}

// ---- the TEM ---------------------------------------------------------------------------

// A vector's length and direction as the TEM computes them (and the tool unit, for the
// sphere's and cylinder's r'): r block-normalised, l2n = r^.r^ exact, y = rsqrt(l2n),
//   l = |r| = 2^shift sqrt(l2n) = 2^shift m 2^parity y 2^k (m y has 2B-3 fractional bits),
//   u = r^ / sqrt(l2n) = r^ y 2^-k in Q1.(B-2) (y has B-1 fractional bits).
struct LengthDirection {
  std::int64_t l = 0;     // X format (the format of r)
  std::int64_t u[3] = {};  // Q1.(B-2) operands; 0 when degenerate
  bool degenerate = false;  // r = 0
};

template <class Fmt>
inline LengthDirection length_direction(const std::int64_t (&r)[3], std::uint32_t* status,
                                        std::uint32_t flag) {
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  const Operands<3> rn = normalize<B, R>(r);
  const i128 l2n = i128(rn.mant[0]) * rn.mant[0] + i128(rn.mant[1]) * rn.mant[1] +
                   i128(rn.mant[2]) * rn.mant[2];
  const RsqrtResult rs = rsqrt_l2<B, R>(l2n);
  LengthDirection out;
  out.degenerate = rs.degenerate;
  out.l = saturate(
      shift_round<R>(i128(rs.mant) * rs.y, 2 * B - 3 - rn.shift - rs.parity - rs.k), W, status,
      flag);
  for (int i = 0; i < 3; ++i)
    out.u[i] = saturate(shift_round<R>(i128(rn.mant[i]) * rs.y, rs.k + 1), B, status, flag);
  return out;
}

// u . v for a unit operand vector u (Q1.(B-2)) and a block-normalised vector v, as a word in
// v's format (the TEM's ldot, the tool unit's along and ldot).
template <class Fmt>
inline std::int64_t along_unit(const std::int64_t* u, const Operands<3>& vn,
                               std::uint32_t* status, std::uint32_t flag) {
  const i128 acc = i128(u[0]) * vn.mant[0] + i128(u[1]) * vn.mant[1] + i128(u[2]) * vn.mant[2];
  return saturate(shift_round<Fmt::kRounding>(acc, Fmt::kFracU - vn.shift), Fmt::kWidth, status,
                  flag);
}

// Every product has Fmt::kOperandBits-bit operands (B): r and dp are block-normalised
// vectors, ldot, d - L, l, T and m normalised words, u a Q1.(B-2) operand.
template <class Fmt, int Arms = 0, bool Damper = false, bool Hardening = false>
inline TemOut tem_edge(const TemIn& in, const MaterialCoefs& m, std::uint32_t* status) {
#pragma HLS PIPELINE II = 1
  static_assert(Arms >= 0 && Arms <= kMaxArms);
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  using S = CoefShifts<Fmt>;
  const std::uint32_t kFlag = kStatusTemSaturated;
  // The arms' products (each saturated to a word) and their exact force sum.
  std::int64_t m_decay[kMaxArms] = {};
  i128 t_arms = 0;
  for (int j = 0; j < Arms; ++j) {
    m_decay[j] = mul_coef_operand<Fmt>(in.m[j], m.gamma[j], S::kGamma, status, kFlag);
    t_arms += mul_coef_operand<Fmt>(in.m[j], m.k2t[j], S::kK2t, status, kFlag);
  }
  std::int64_t r[3], dp[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = saturate(i128(in.xe[i]) - in.xs[i], W, status, kFlag);
    dp[i] = saturate(i128(in.pe[i]) - in.ps[i], W, status, kFlag);
  }
  const std::int64_t ds = saturate(i128(in.d) - in.L, W, status, kFlag);
  const Operands<3> dpn = normalize<B, R>(dp);
  const LengthDirection ld = length_direction<Fmt>(r, status, kFlag);
  if (ld.degenerate) *status |= kStatusDegenerateEdge;
  const std::int64_t l = ld.l;
  const std::int64_t* u = ld.u;
  const std::int64_t ldot = along_unit<Fmt>(u, dpn, status, kFlag);
  // This edge's coefficients: the material's, or with the force-dependent damper the
  // material's scaled by the damper's state (which depends on ds alone, so the RTL
  // computes it beside the length).
  // With strain hardening they depend on l as well (and the hardened stiffness adds a
  // term of its own on ldot, cth).
  Coef alpha = m.alpha, beta = m.beta, kt = m.kt, ct = m.ct;
  std::int64_t t_lead = 0;  // the arms' lead on ldot (in ct without damper and hardening)
  std::int64_t t_hard = 0;  // cth ldot
  if constexpr (Damper || Hardening) {
    DampedCoefs dc;
    if constexpr (Hardening) {
      dc = hardened_coefs<Fmt, Damper>(ds, l, in.L, m, status);
      t_hard = mul_coef_operand<Fmt>(ldot, dc.cth, S::kCt, status, kFlag);
    } else {
      dc = damper_coefs<Fmt>(ds, m, status);
    }
    alpha = dc.alpha;
    beta = dc.beta;
    kt = dc.kt;
    ct = dc.ct;
    t_lead = mul_coef_operand<Fmt>(ldot, m.ka, S::kCt, status, kFlag);
  }
  const std::int64_t dd_beta = mul_coef_operand<Fmt>(ldot, beta, S::kBeta, status, kFlag);
  const std::int64_t dd_alpha = mul_coef_operand<Fmt>(ds, alpha, S::kAlpha, status, kFlag);
  const std::int64_t dd = saturate(i128(dd_beta) - dd_alpha, W, status, kFlag);
  const std::int64_t t_spring = mul_coef_operand<Fmt>(ds, kt, S::kKt, status, kFlag);
  const std::int64_t t_damper = mul_coef_operand<Fmt>(ldot, ct, S::kCt, status, kFlag);
  TemOut out;
  // The arms' force joins the tension in one wide sum, so it saturates once.
  const std::int64_t tension =
      saturate(i128(t_spring) + t_damper + t_lead + t_hard + t_arms, W, status, kFlag);
  for (int j = 0; j < Arms; ++j) {
    const std::int64_t dm = saturate(i128(ldot) - m_decay[j], W, status, kFlag);
    out.m[j] =
        saturate(i128(in.m[j]) + shift_round<R>(dm, Fmt::kFracP - Fmt::kFracX), W, status, kFlag);
  }
  const std::int64_t lo = mul_coef_operand<Fmt>(l, m.a_min, S::kClamp, status, kFlag);
  const std::int64_t hi = mul_coef_operand<Fmt>(l, m.a_max, S::kClamp, status, kFlag);
  const Operands<1> tn = normalize<B, R>(tension);
  for (int i = 0; i < 3; ++i)
    out.f[i] = saturate(shift_round<R>(i128(tn.mant[0]) * u[i], Fmt::kFracU - tn.shift), W,
                        status, kFlag);
  std::int64_t d_new =
      saturate(i128(in.d) + shift_round<R>(dd, Fmt::kFracP - Fmt::kFracX), W, status, kFlag);
  if ((m.flags & kClampLowEnable) && d_new < lo) d_new = lo;
  if ((m.flags & kClampHighEnable) && d_new > hi) d_new = hi;
  out.d = d_new;
  return out;
}

// ---- volume preservation -----------------------------------------------------------------

// A packed coefficient word (frame::kCoefShiftPos): mantissa [17:0], shift + bias [23:18].
inline Coef unpack_coef(std::uint32_t w) {
  Coef c;
  const std::int32_t mant = static_cast<std::int32_t>(w << (32 - kCoefMantBits));
  c.mant = mant >> (32 - kCoefMantBits);  // sign-extend the mantissa
  c.shift = static_cast<std::int32_t>((w >> frame::kCoefShiftPos) & ((1u << kCoefShiftBits) - 1)) -
            kCoefShiftBias;
  return c;
}

// The packed word of a coefficient (the inverse of unpack_coef).
inline std::uint32_t pack_coef(const Coef& c) {
  return (static_cast<std::uint32_t>(c.mant) & ((1u << kCoefMantBits) - 1)) |
         (static_cast<std::uint32_t>(c.shift + kCoefShiftBias) << frame::kCoefShiftPos);
}

// normalize for values wider than a word (exact products).
template <int B, Rounding R, int N>
inline Operands<N> normalize_wide(const i128 (&v)[N]) {
  i128 bits = 0;
  for (int i = 0; i < N; ++i) bits |= v[i] < 0 ? ~v[i] : v[i];
  Operands<N> out;
  out.shift = operand_shift<B>(bit_length(bits));
  for (int i = 0; i < N; ++i) out.mant[i] = to_operand<B, R>(v[i], out.shift);
  return out;
}

// One tetrahedron (a, b, c, d) of a model with volume preservation (rheo::Simulator's
// add_volume_forces): pressure p = -kv (V - V0) / |V0| and the force p dV/dx_k on each
// vertex. In words (CoefShifts::kVolume, docs/hardware.md "Volume preservation"):
//   e_k = x_k - x_a (k = b, c, d; exact),  g_b = e_c x e_d,  V6 = e_b . g_b
//   D = V6 - V6_0 (V format, kFracV fractional bits)
//   P = -c D,  c = kv Lu^2 / (36 Fu |V0|)
//   g_c = e_d x e_b,  g_d = e_b x e_c,  g_a = -(g_b + g_c + g_d)     (g_k = 6 dV/dx_k)
//   f_k = P g_k
// e_k, g_b and V6 with kVolOperandBits-bit operands (exact for the hardware format), g_c, g_d
// and the products after D with the format's operands (g_b rounded to their scale).
// A triangle (a, b, c) of a 2-D model, whose particles move in the x-z plane, runs as the
// tetrahedron with the virtual fourth vertex d = a + Y y^ (y > 0): e_d = (0, Y, 0), so
//   V6 = e_b . (e_c x e_d) = 2 Y A,  A = ((b-a)_z (c-a)_x - (b-a)_x (c-a)_z) / 2
// (rheo::Simulator's signed area), g_b = 2 Y dA/db, g_c = 2 Y dA/dc; g_d is left out
// (g_d = 0, so f_d = 0 and g_a = -(g_b + g_c) = 2 Y dA/da), and
//   c = kv Lu / (4 Y^2 Fu |A0|)  (kv in N/m; Y, A0 in Lu units),
// which gives the reference's f_k = -kv (A - A0) / |A0| dA/dx_k. The host picks Y, a power
// of two no larger than the rest element's largest difference, so that Y does not set the
// operands' exponent (docs/hardware.md "Volume preservation").
struct VolumeIn {
  std::int64_t x[4][3];  // vertices a, b, c, d (X format; d unused for a triangle)
  std::int64_t v0 = 0;   // V6_0: six times the rest volume (V format)
  Coef c;                // kv Lu^2 / (36 Fu |V0|), or a triangle's kv Lu / (4 Y^2 Fu |A0|)
  std::int64_t y = 0;    // a triangle's Y (X format, 1 .. 2^32 - 1); 0 for a tetrahedron
};

struct VolumeOut {
  std::int64_t f[4][3];     // force on a, b, c, d (F format)
  bool saturated[4][3];     // which of them saturated (kStatusVolumeSaturated)
};

// The intermediate values of one volume_element call, filled when the caller asks (the RTL
// test checks which operand holds, exponents and shift clamps its elements reach).
struct VolumeTrace {
  i128 e[9];    // e_b, e_c, e_d
  i128 gb[3];   // g_b, exact
  i128 v6;      // V6 (V format)
  i128 d, p;    // D and -c D^ before their normalisation
  i128 g[12];   // g_a, g_b, g_c, g_d in e^'s units
  Operands<9> ev, en;
  Operands<3> gv;
  Operands<1> dn, pn;
  Operands<12> gn;
  int shift_raw;  // the force products' shift before its clamp
};

template <class Fmt>
inline VolumeOut volume_element(const VolumeIn& in, std::uint32_t* status,
                                VolumeTrace* trace = nullptr) {
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr int VB = kVolOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  VolumeTrace t;
  i128* e = t.e;
  const bool triangle = in.y != 0;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) e[3 * k + i] = i128(in.x[k + 1][i]) - in.x[0][i];
  if (triangle)
    for (int i = 0; i < 3; ++i) e[6 + i] = i == 1 ? i128(in.y) : i128(0);
  // V6 = e_b . (e_c x e_d) with wide operands.
  t.ev = normalize_wide<VB, R, 9>(t.e);
  const std::int64_t* eb = &t.ev.mant[0];
  const std::int64_t* ec = &t.ev.mant[3];
  const std::int64_t* ed = &t.ev.mant[6];
  t.gb[0] = i128(ec[1]) * ed[2] - i128(ec[2]) * ed[1];
  t.gb[1] = i128(ec[2]) * ed[0] - i128(ec[0]) * ed[2];
  t.gb[2] = i128(ec[0]) * ed[1] - i128(ec[1]) * ed[0];
  t.gv = normalize_wide<VB, R, 3>(t.gb);
  const i128 v6_raw =
      i128(eb[0]) * t.gv.mant[0] + i128(eb[1]) * t.gv.mant[1] + i128(eb[2]) * t.gv.mant[2];
  // v6_raw 2^(3 ev.shift + gv.shift) in units of 2^-3FracX Lu^3.
  t.v6 = shift_round<R>(v6_raw, 3 * Fmt::kFracX - Fmt::kFracV - 3 * t.ev.shift - t.gv.shift);
  t.d = t.v6 - in.v0;
  t.dn = normalize_wide<B, R, 1>({t.d});
  // P = -c D as an operand: value pn 2^(pn.shift + dn.shift - c.shift).
  t.p = -(i128(t.dn.mant[0]) * in.c.mant);
  t.pn = normalize_wide<B, R, 1>({t.p});
  // The gradients with the format's operands: value g 2^(2 en.shift), X^2 units.
  t.en = normalize_wide<B, R, 9>(t.e);
  const std::int64_t* nb = &t.en.mant[0];
  const std::int64_t* nc = &t.en.mant[3];
  const std::int64_t* nd = &t.en.mant[6];
  i128* g = t.g;
  for (int i = 0; i < 3; ++i)
    g[3 + i] = shift_round<R>(t.gb[i], 2 * t.en.shift - 2 * t.ev.shift);
  g[6] = i128(nd[1]) * nb[2] - i128(nd[2]) * nb[1];
  g[7] = i128(nd[2]) * nb[0] - i128(nd[0]) * nb[2];
  g[8] = i128(nd[0]) * nb[1] - i128(nd[1]) * nb[0];
  g[9] = triangle ? 0 : i128(nb[1]) * nc[2] - i128(nb[2]) * nc[1];
  g[10] = triangle ? 0 : i128(nb[2]) * nc[0] - i128(nb[0]) * nc[2];
  g[11] = triangle ? 0 : i128(nb[0]) * nc[1] - i128(nb[1]) * nc[0];
  for (int i = 0; i < 3; ++i) g[i] = -(g[3 + i] + g[6 + i] + g[9 + i]);
  t.gn = normalize_wide<B, R, 12>(t.g);
  t.shift_raw = CoefShifts<Fmt>::kVolume + in.c.shift - t.pn.shift - t.dn.shift - t.gn.shift -
                2 * t.en.shift;
  // Clamped to [-64, 2B]: a larger left shift saturates any non-zero product anyway, and a
  // larger right shift rounds every product (|pn gn| <= 2^(2B-2)) to 0 anyway.
  const int shift = std::clamp(t.shift_raw, -64, 2 * B);
  VolumeOut out;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) {
      std::uint32_t sat = 0;
      out.f[k][i] = saturate(shift_round<R>(i128(t.pn.mant[0]) * t.gn.mant[3 * k + i], shift),
                             W, &sat, kStatusVolumeSaturated);
      out.saturated[k][i] = sat != 0;
      *status |= sat;
    }
  if (trace) *trace = t;
  return out;
}

// ---- the tool unit's registers (the unit itself: hls/tool_contact.hpp) ----------------

enum ToolKind : std::uint32_t {
  kToolOff = 0,
  kToolPlane = 1,
  kToolSphere = 2,
  kToolCylinder = 3,
};

// The tool registers of one step (the core holds them constant during the MPM pass).
struct ToolRegs {
  std::uint32_t kind = kToolOff;
  std::int64_t c[3] = {0, 0, 0};   // position now (X format): plane point, sphere or cylinder centre
  std::int64_t dc[3] = {0, 0, 0};  // displacement over the step (P format)
  std::int64_t a[3] = {0, 0, 0};   // unit normal (plane) or axis (cylinder), Q1.(B-2) operands
  std::int64_t reach = 0;          // X format: eps (plane), radius + eps (sphere, cylinder)
  std::int64_t half_length = 0;    // X format: half the cylinder's length
  Coef kt;                         // k Lu / Fu (CoefShifts::kKt)
  Coef ct;                         // c Lu / (dt Fu) (CoefShifts::kCt)
  Coef mu;                         // Coulomb friction coefficient (CoefShifts::kMu)
  Coef spin;                       // a cylinder's surface displacement over the step, dq R,
                                   // in P-format LSBs (CoefShifts::kSpin; 0 otherwise)
};

struct ToolOut {
  std::int64_t f[3] = {0, 0, 0};  // force on the particle (F format)
  bool contact = false;
};

// One particle's contact with the tool (defined in hls/tool_contact.hpp).
template <class Fmt>
ToolOut tool_particle(const std::int64_t x[3], const std::int64_t p[3], const Coef& minv,
                      const ToolRegs& t, std::uint32_t* status);

// ---- MPM ------------------------------------------------------------------------------

struct MpmParticle {
  std::int64_t x[3], p[3];  // state
  std::int64_t x0[3];       // home position (fixed particles)
  Coef minv;                // Fu dt^2 / (m Lu)
  std::uint32_t flags = 0;  // CoreParticleFlag
};

struct MpmGlobals {
  std::int64_t g[3] = {0, 0, 0};  // gravity displacement per step^2 (P format)
  std::int64_t plate_z = 0;       // X format
  bool plate_enable = false;
  bool floor_enable = false;
  // Hold while pushing (frame::kControlPlateHold). A particle the plate held in the previous
  // step sits exactly at that step's plate height, so the core needs no per-particle bit:
  // it keeps the previous plate height (valid from the second step after a control write).
  bool plate_hold = false;
  std::int64_t plate_z_prev = 0;
  bool plate_prev_valid = false;
};

// The plate height of the next step (the core's StRunPlate): the current one becomes the
// previous one.
inline void start_step(MpmGlobals& g, std::int64_t plate_z) {
  g.plate_z_prev = g.plate_z;
  g.plate_prev_valid = true;
  g.plate_z = plate_z;
}

// A write of the control register: the enables, and no previous plate height yet.
inline void write_control(MpmGlobals& g, bool floor, bool plate, bool plate_hold) {
  g.floor_enable = floor;
  g.plate_enable = plate;
  g.plate_hold = plate_hold;
  g.plate_prev_valid = false;
}

// Updates one particle in place; returns the z force to add to the plate accumulator
// (0 when the particle is not held by the plate).
template <class Fmt>
inline std::int64_t mpm_particle(MpmParticle& q, const std::int64_t f[3], const MpmGlobals& g,
                                 std::uint32_t* status) {
#pragma HLS PIPELINE II = 1
  constexpr int W = Fmt::kWidth;
  constexpr Rounding R = Fmt::kRounding;
  const std::uint32_t kFlag = kStatusMpmSaturated;
  std::int64_t p[3], x[3];
  for (int i = 0; i < 3; ++i) {
    const std::int64_t dp = mul_coef<Fmt>(f[i], q.minv, CoefShifts<Fmt>::kMinv, status, kFlag);
    const std::int64_t p1 = saturate(i128(q.p[i]) + dp, W, status, kFlag);
    p[i] = saturate(i128(p1) + g.g[i], W, status, kFlag);
    x[i] =
        saturate(i128(q.x[i]) + shift_round<R>(p[i], Fmt::kFracP - Fmt::kFracX), W, status, kFlag);
  }
  std::int64_t plate_force = 0;
  // The clamp bound: the plate's step since the particle's position, in P units.
  std::uint32_t lim_status = 0;
  const std::int64_t lim =
      saturate(shift_round<R>(i128(g.plate_z) - q.x[2], -(Fmt::kFracP - Fmt::kFracX)), W,
               &lim_status, kFlag);
  // A particle that sat on the plate (at the previous step's plate height) stays on it
  // while its new displacement exceeds the plate's step (p.z > lim): the double reference's
  // rule v > V_plate, decided on the P word. Decided on the rounded position instead, it
  // needed the particle to move half an X LSB beyond the plate, and a held particle whose
  // force moves it less than that per step (dt^2 f / m, large mass scales) was dropped with
  // its force: exact-zero plate forces (docs/hardware.md, "Plate rules").
  const bool on_plate_before = g.plate_prev_valid && q.x[2] == g.plate_z_prev;
  if (q.flags & kCoreFixed) {
    for (int i = 0; i < 3; ++i) {
      x[i] = q.x0[i];
      p[i] = 0;
    }
  } else if ((q.flags & kCorePlate) && g.plate_enable &&
             (x[2] > g.plate_z || (on_plate_before && p[2] > lim) ||
              (g.plate_hold && on_plate_before && f[2] > 0))) {
    // The held particle moves with the plate: p.z <= plate_z - z_start (as the reference
    // simulator does), so the edges see the plate's strain rate; a particle kept because
    // it pushes moves exactly with the plate.
    *status |= lim_status;
    if (x[2] > g.plate_z || p[2] > lim) {
      if (p[2] > lim) p[2] = lim;
    } else {
      p[2] = lim;
    }
    x[2] = g.plate_z;
    plate_force = f[2];
  } else if (g.floor_enable && x[2] < 0) {
    x[2] = 0;
    if (p[2] < 0) p[2] = 0;
  }
  for (int i = 0; i < 3; ++i) {
    q.x[i] = x[i];
    q.p[i] = p[i];
  }
  return plate_force;
}

// ---- the core's memories and one step ------------------------------------------------

// Particles are partitioned over the lanes: particle i lives in bank i % lanes at local
// address i / lanes. Edge slot t belongs to lane t % lanes and schedule row t / lanes; the
// slot's start particle lives in the lane's own bank, its end particle in bank e_bank.
// Empty slots (valid = false) are bubbles of the schedule.
// A volume element (Volume cores) takes two consecutive rows of one lane: the first slot
// (element) holds vertices a (start) and b (end) and V6_0 split over L (low 32 bits) and d
// (the rest); the second (element, second) holds c and d, the packed coefficient in L and,
// for a triangle of a 2-D model, Y in d (0 for a tetrahedron; d's particle is then unused).
// The core keeps one element half per lane: a second half that does not follow a first
// half in the lane's previous row, or an element slot on a core without the element unit,
// is a schedule conflict.
struct EdgeEntry {
  bool valid = false;
  bool element = false;  // half of a volume element, not an edge
  bool second = false;   // the element's second half
  std::uint32_t s_local = 0;  // start particle: local address in the lane's bank
  std::uint32_t e_bank = 0;   // end particle: bank and local address
  std::uint32_t e_local = 0;
  std::uint32_t material = 0;
  std::int64_t L = 0, d = 0;
  std::int64_t m[kMaxArms] = {};  // Maxwell-arm extensions (arms of the core only)
};

struct CoreMemory {
  MpmParticle particles[kMaxParticles];  // by particle index i = local * lanes + bank
  EdgeEntry edges[kMaxEdges];            // by slot t = row * lanes + lane
  MaterialCoefs materials[kMaxMaterials];
  // Per particle, the sums of the forces of the edges where it is the start and where it
  // is the end (the RTL's two accumulator memories per bank); exact, cleared by the MPM.
  std::int64_t force_start[kMaxParticles][3] = {};
  std::int64_t force_end[kMaxParticles][3] = {};
  std::uint32_t num_particles = 0;
  std::uint32_t edge_rows = 0;  // rows of the edge schedule (edge_rows * lanes slots)
  std::uint32_t lanes = 1;
  MpmGlobals globals;
  // The tool unit (a core built with it): its registers, and the reaction force of the
  // last step (F format words, -sum of the tool's forces on the particles).
  ToolRegs tool;
  std::int64_t tool_reaction[3] = {0, 0, 0};
  std::uint32_t status = 0;
  std::uint32_t step_count = 0;
};

// One time step; returns the plate force word (F format). The edge and particle loops are
// the core's edge pass and MPM pass. Every TEM reads the particle state of the previous
// step (the MPM pass starts after the edge pass), and the force sums are exact (wide,
// saturated only when narrowed for the MPM), so neither the slot order nor the lane
// assignment changes any bit.
// With Tool (a core with the tool unit), each particle that is not fixed first meets the
// tool: the tool's force joins its force sum (saturated once more) before the MPM, and the
// reaction sums the forces exactly (hls/tool_contact.hpp).
template <class Fmt, int Arms = 0, bool Damper = false, bool Hardening = false,
          bool Volume = false, bool Tool = false>
inline std::int64_t core_step(CoreMemory& mem) {
  constexpr int W = Fmt::kWidth;
  const std::uint32_t lanes = mem.lanes;
  // Per lane, the first half of an element whose second half may come in the next row.
  bool first_pending[kMaxLanes] = {};
  std::uint32_t first_slot[kMaxLanes] = {};
edge_pass:
  for (std::uint32_t row = 0; row < mem.edge_rows; ++row) {
#pragma HLS PIPELINE II = 1
#pragma HLS LOOP_TRIPCOUNT max = 65536
    std::uint32_t end_banks_used = 0;
    for (std::uint32_t lane = 0; lane < lanes; ++lane) {
#pragma HLS UNROLL
      const std::uint32_t slot = row * lanes + lane;
      if (slot >= std::uint32_t(kMaxEdges)) break;
      EdgeEntry& edge = mem.edges[slot];
      const bool pending = first_pending[lane];
      first_pending[lane] = false;
      if (!edge.valid) continue;
      // The crossbar serves one end particle per bank and row (the host's schedule).
      if (edge.e_bank >= lanes || (end_banks_used & (1u << edge.e_bank)))
        mem.status |= kStatusScheduleConflict;
      end_banks_used |= 1u << (edge.e_bank & 31u);
      const std::uint32_t si = edge.s_local * lanes + lane;
      const std::uint32_t ei = edge.e_local * lanes + edge.e_bank;
      if (si >= std::uint32_t(kMaxParticles) || ei >= std::uint32_t(kMaxParticles)) continue;
      if (edge.element) {
        if (!Volume || (edge.second && !pending)) {
          mem.status |= kStatusScheduleConflict;
        } else if (!edge.second) {
          first_pending[lane] = true;
          first_slot[lane] = slot;
        } else {
          const EdgeEntry& first = mem.edges[first_slot[lane]];
          const std::uint32_t ai = first.s_local * lanes + lane;
          const std::uint32_t bi = first.e_local * lanes + first.e_bank;
          const std::uint32_t vertex[4] = {ai, bi, si, ei};
          VolumeIn vin;
          for (int k = 0; k < 4; ++k)
            for (int i = 0; i < 3; ++i) vin.x[k][i] = mem.particles[vertex[k]].x[i];
          vin.v0 = static_cast<std::int64_t>((std::uint64_t(first.d) << 32) |
                                             std::uint32_t(first.L));
          vin.c = unpack_coef(std::uint32_t(edge.L));
          vin.y = std::int64_t(std::uint32_t(edge.d));  // the d word: a triangle's Y, or 0
          const VolumeOut out = volume_element<Fmt>(vin, &mem.status);
          for (int i = 0; i < 3; ++i) {
            mem.force_start[ai][i] += out.f[0][i];
            mem.force_end[bi][i] += out.f[1][i];
            mem.force_start[si][i] += out.f[2][i];
            mem.force_end[ei][i] += out.f[3][i];
          }
        }
        continue;
      }
      const MpmParticle& s = mem.particles[si];
      const MpmParticle& e = mem.particles[ei];
      TemIn in;
      for (int i = 0; i < 3; ++i) {
        in.xs[i] = s.x[i];
        in.xe[i] = e.x[i];
        in.ps[i] = s.p[i];
        in.pe[i] = e.p[i];
      }
      in.d = edge.d;
      in.L = edge.L;
      for (int j = 0; j < Arms; ++j) in.m[j] = edge.m[j];
      const TemOut out = tem_edge<Fmt, Arms, Damper, Hardening>(in, mem.materials[edge.material], &mem.status);
      for (int i = 0; i < 3; ++i) {
        mem.force_start[si][i] += out.f[i];
        mem.force_end[ei][i] -= out.f[i];
      }
      edge.d = out.d;
      for (int j = 0; j < Arms; ++j) edge.m[j] = out.m[j];
    }
  }
  i128 plate_acc = 0;
  i128 tool_acc[3] = {0, 0, 0};
mpm_pass:
  for (std::uint32_t i = 0; i < mem.num_particles && i < std::uint32_t(kMaxParticles); ++i) {
#pragma HLS PIPELINE II = 1
#pragma HLS LOOP_TRIPCOUNT max = 4096
    std::int64_t f[3];
    for (int a = 0; a < 3; ++a) {
      f[a] = saturate(i128(mem.force_start[i][a]) + mem.force_end[i][a], W, &mem.status,
                      kStatusMpmSaturated);
      mem.force_start[i][a] = 0;
      mem.force_end[i][a] = 0;
    }
    if constexpr (Tool) {
      const MpmParticle& q = mem.particles[i];
      if (!(q.flags & kCoreFixed)) {
        const ToolOut t = tool_particle<Fmt>(q.x, q.p, q.minv, mem.tool, &mem.status);
        for (int a = 0; a < 3; ++a) {
          f[a] = saturate(i128(f[a]) + t.f[a], W, &mem.status, kStatusMpmSaturated);
          tool_acc[a] += t.f[a];
        }
      }
    }
    plate_acc += mpm_particle<Fmt>(mem.particles[i], f, mem.globals, &mem.status);
  }
  if constexpr (Tool) {
    for (int a = 0; a < 3; ++a)
      mem.tool_reaction[a] = saturate(-tool_acc[a], W, &mem.status, kStatusToolReactionSaturated);
  }
  ++mem.step_count;
  return saturate(plate_acc, W, &mem.status, kStatusPlateSaturated);
}

}  // namespace rheo::hls

// The tool unit's definition (it uses the primitives above).
#include "hls/tool_contact.hpp"
