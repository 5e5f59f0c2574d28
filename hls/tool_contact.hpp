// Bit-true model of the tool unit: the contact of one particle with one rigid tool (a plane,
// a sphere or a cylinder), per particle in the MPM pass. It mirrors rtl/rheo_tool.sv
// operation for operation and is the fixed-point form of sim/tool.hpp's penalty contact
// without friction:
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
//   contact: in reach and F_n > 0;  f = F_n u (the force on the particle), else 0.
// This is a unilateral Voigt element between the particle and the tool's surface: with
// ds = delta - eps (delta the signed distance to the surface) and ldot = n . (v - v_tool) dt,
// F_n = k (eps - delta) - c ddelta/dt, as the reference's penalty_force. A cylinder's spin
// moves its surface along the surface, so it does not enter ldot (it matters only for
// friction, which this unit does not compute).
// Every product has Fmt::kOperandBits-bit operands like the TEM's (r, dp, r' block-normalised,
// along, ldot, ds and F_n normalised words). Saturation inside the unit raises
// kStatusMpmSaturated only for a particle in reach: a particle far from the tool may
// overflow its own distance words, which then only say that it is out of reach.
#pragma once

#include <cstdint>

#include "hls/rheo_kernel.hpp"

namespace rheo::hls {

// (ToolKind, ToolRegs and ToolOut are declared in hls/rheo_kernel.hpp, beside the core's
// memory that holds the registers.)
template <class Fmt>
ToolOut tool_particle(const std::int64_t x[3], const std::int64_t p[3], const ToolRegs& t,
                      std::uint32_t* status) {
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
  ToolOut out;
  if (!in_reach) return out;
  *status |= st;
  const Operands<1> fnn = normalize<B, R>(fn);
  std::uint32_t fst = 0;
  for (int i = 0; i < 3; ++i)
    out.f[i] = saturate(shift_round<R>(i128(fnn.mant[0]) * u[i], Fmt::kFracU - fnn.shift), W,
                        &fst, kFlag);
  out.contact = fn > 0;
  if (!out.contact) {
    for (int i = 0; i < 3; ++i) out.f[i] = 0;
  } else {
    *status |= fst;
  }
  return out;
}

}  // namespace rheo::hls
