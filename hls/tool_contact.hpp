// Bit-true model of the tool unit: the contact of one particle with one rigid tool (a plane,
// a sphere or a cylinder), per particle in the MPM pass. It mirrors rtl/rheo_tool.sv
// operation for operation and is the fixed-point form of sim/tool.hpp's penalty contact
// with Coulomb kinetic friction:
//   r = x - c, dp = p - dc                      (c: the tool's position now, dc: its
//                                                displacement over the step, P format)
//   along = a . r                               (a: unit normal / axis, Q1.(B-2) operands)
//   plane:    l = along,                  u = a
//   sphere:   r' = r                      l = |r'|, u = r' / l   (rsqrt, as the TEM)
//   cylinder: r' = r - along a            l = |r'|, u = r' / l
//   ldot = u . dp,  ds = l - reach              (reach: eps for a plane, radius + eps for a
//                                                sphere or cylinder)
//   T = kt ds + ct ldot,  F_n = -T
//   in reach: ds < 0 (and |along| <= half length for a cylinder; r' != 0)
//   contact: in reach and F_n > 0
// Friction acts against the tangential displacement relative to the tool's surface,
//   dp_t = dp - ldot u - spin (a x u)           (spin = dq R: a turning cylinder's surface
//                                                moves by spin along a x u over the step)
//   l_t = |dp_t|, t = dp_t / l_t                (the same length unit as l and u)
//   F_t = min(mu F_n, l_t / minv)               (minv = Fu dt^2 / (m Lu): l_t / minv is the
//                                                force that stops the slide in one step)
//   f = F_n u - F_t t (the force on the particle) in contact, else 0.
// 1/minv comes from the reciprocal unit (seed table and one Newton-Raphson step, as the
// damper's 1/s): minv = mant 2^-shift, mant = m 2^(nb-1), 1/m ~ y. The cap l_t / minv never
// raises a flag (a cap beyond the word only means mu F_n is the smaller); a particle with
// minv <= 0 has no cap.
// This is a unilateral Voigt element between the particle and the tool's surface: with
// ds = delta - eps (delta the signed distance to the surface) and ldot = n . (v - v_tool) dt,
// F_n = k (eps - delta) - c ddelta/dt, as the reference's penalty_force. A cylinder's spin
// moves its surface along the surface, so it enters dp_t, not ldot.
// Every product has Fmt::kOperandBits-bit operands like the TEM's (r, dp, r', dp_t
// block-normalised, along, ldot, ds, F_n, l_t and F_t normalised words). Saturation inside
// the unit raises kStatusMpmSaturated only for a particle in reach: a particle far from the
// tool may overflow its own distance words, which then only say that it is out of reach.
#pragma once

#include <cstdint>

#include "hls/rheo_kernel.hpp"

namespace rheo::hls {

// (ToolKind, ToolRegs and ToolOut are declared in hls/rheo_kernel.hpp, beside the core's
// memory that holds the registers.)
template <class Fmt>
ToolOut tool_particle(const std::int64_t x[3], const std::int64_t p[3], const Coef& minv,
                      const ToolRegs& t, std::uint32_t* status) {
  constexpr int W = Fmt::kWidth;
  constexpr int B = Fmt::kOperandBits;
  constexpr Rounding R = Fmt::kRounding;
  using S = CoefShifts<Fmt>;
  const std::uint32_t kFlag = kStatusMpmSaturated;
  std::uint32_t st = 0;  // this particle's flags: they count only in reach
  std::int64_t r[3], dp[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = saturate(i128(x[i]) - t.c[i], W, &st, kFlag);
    dp[i] = saturate(i128(p[i]) - t.dc[i], W, &st, kFlag);
  }
  const Operands<3> rn = normalize<B, R>(r);
  const Operands<3> dpn = normalize<B, R>(dp);
  const std::int64_t along = along_unit<Fmt>(t.a, rn, &st, kFlag);
  // the radial part r' (a cylinder's; a sphere's is r)
  std::int64_t rp[3];
  const Operands<1> an = normalize<B, R>(along);
  for (int i = 0; i < 3; ++i) {
    const std::int64_t proj = saturate(
        shift_round<R>(i128(an.mant[0]) * t.a[i], Fmt::kFracU - an.shift), W, &st, kFlag);
    rp[i] = t.kind == kToolCylinder ? saturate(i128(r[i]) - proj, W, &st, kFlag) : r[i];
  }
  // |r'| and r' / |r'| as the TEM computes l and u
  const LengthDirection ld = length_direction<Fmt>(rp, &st, kFlag);
  const bool plane = t.kind == kToolPlane;
  const std::int64_t l = plane ? along : ld.l;
  const std::int64_t* u = plane ? t.a : ld.u;
  const std::int64_t ldot = along_unit<Fmt>(u, dpn, &st, kFlag);
  const std::int64_t ds = saturate(i128(l) - t.reach, W, &st, kFlag);
  const std::int64_t t_spring = mul_coef_operand<Fmt>(ds, t.kt, S::kKt, &st, kFlag);
  const std::int64_t t_damper = mul_coef_operand<Fmt>(ldot, t.ct, S::kCt, &st, kFlag);
  const std::int64_t tension = saturate(i128(t_spring) + t_damper, W, &st, kFlag);
  const std::int64_t fn = saturate(-i128(tension), W, &st, kFlag);
  const bool along_ok = t.kind != kToolCylinder ||
                        (along <= t.half_length && along >= -t.half_length);
  const bool in_reach = t.kind != kToolOff && ds < 0 && along_ok && (plane || !ld.degenerate);
  // The friction path: dp_t, its length and direction, the cap and F_t.
  const Operands<1> ldn = normalize<B, R>(ldot);
  std::int64_t cross[3], dpt[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    // (a x u)_i in Q1.(B-2): |a x u| <= 1, so only rounding can reach the operand's limit
    cross[i] = saturate(shift_round<R>(i128(t.a[j]) * u[k] - i128(t.a[k]) * u[j], Fmt::kFracU),
                        B, &st, kFlag);
  }
  for (int i = 0; i < 3; ++i) {
    const std::int64_t normal = saturate(
        shift_round<R>(i128(ldn.mant[0]) * u[i], Fmt::kFracU - ldn.shift), W, &st, kFlag);
    const std::int64_t slip = saturate(
        shift_round<R>(i128(cross[i]) * t.spin.mant, t.spin.shift + S::kSpin), W, &st, kFlag);
    dpt[i] = saturate(i128(dp[i]) - normal - slip, W, &st, kFlag);
  }
  const LengthDirection ldt = length_direction<Fmt>(dpt, &st, kFlag);
  const Operands<1> fnn = normalize<B, R>(fn);
  const std::int64_t mu_fn = mul_coef_operand<Fmt>(fn, t.mu, S::kMu, &st, kFlag);
  // l_t / minv = l_t 2^shift / mant, 1/mant = y 2^-(B-2) 2^(1-nb), shifted to F format
  std::int64_t cap = (std::int64_t(1) << (W - 1)) - 1;
  if (minv.mant > 0) {
    const int nb = bit_length(minv.mant);
    const std::int64_t y = recip_mantissa<B, R>(to_operand<B, R>(minv.mant, nb - (B - 1)));
    const Operands<1> ltn = normalize<B, R>(ldt.l);
    std::uint32_t quiet = 0;  // beyond the word: mu F_n is the smaller
    cap = saturate(shift_round<R>(i128(ltn.mant[0]) * y, (B - 2) + nb - 1 - minv.shift -
                                                             S::kMinv - ltn.shift),
                   W, &quiet, kFlag);
  }
  const std::int64_t ft = mu_fn < cap ? mu_fn : cap;
  const Operands<1> ftn = normalize<B, R>(ft);
  ToolOut out;
  if (!in_reach) return out;
  *status |= st;
  std::uint32_t fst = 0;
  for (int i = 0; i < 3; ++i) {
    const std::int64_t fn_u = saturate(
        shift_round<R>(i128(fnn.mant[0]) * u[i], Fmt::kFracU - fnn.shift), W, &fst, kFlag);
    const std::int64_t ft_t = saturate(
        shift_round<R>(i128(ftn.mant[0]) * ldt.u[i], Fmt::kFracU - ftn.shift), W, &fst, kFlag);
    out.f[i] = saturate(i128(fn_u) - ft_t, W, &fst, kFlag);
  }
  out.contact = fn > 0;
  if (!out.contact) {
    for (int i = 0; i < 3; ++i) out.f[i] = 0;
  } else {
    *status |= fst;
  }
  return out;
}

}  // namespace rheo::hls
