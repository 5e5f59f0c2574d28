// The RTL TEM (rtl/rheo_tem.sv, verilated alone) against the bit-true tem_edge on random
// inputs fed one per clock: every output word and flag must be equal. Run for four
// variants: the baseline TEM (Vrheo_tem), the ones with one, four and eight parallel
// Maxwell arms (MaxwellArms = 1, 4, 8: Vrheo_tem_arm, Vrheo_tem_arms4, Vrheo_tem_arms8),
// which also carry each arm's extension m_j and two more coefficients per arm, and the ones
// with the force-dependent series damper (SeriesDamper = 1: Vrheo_tem_damper, and with eight
// arms Vrheo_tem_damper_arms8), whose six coefficients per material drive the edge's
// alpha, beta, kt, ct through the 2^-f table and the reciprocal, and the one with strain
// hardening (StrainHardening = 1: Vrheo_tem_hardening, HardTemExtra clocks longer), whose three
// coefficients and the edge's length and L drive alpha, beta, kt, ct and cth, and the one
// with every effect (eight arms, the damper and hardening: Vrheo_tem_every, whose damper
// follows the hardened spring's extension).
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_tem.h"
#include "Vrheo_tem_arm.h"
#include "Vrheo_tem_arms4.h"
#include "Vrheo_tem_arms8.h"
#include "Vrheo_tem_damper.h"
#include "Vrheo_tem_damper_arms8.h"
#include "Vrheo_tem_hardening.h"
#include "Vrheo_tem_every.h"
#pragma GCC diagnostic pop

#include <deque>
#include <random>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "tests/hw/rtl_harness.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
using S = CoefShifts<Fmt>;
constexpr int kEdges = 20000;

struct Expected {
  int idx;
  TemOut out;
  std::uint32_t status;
};

// Drives kEdges random edges (10 % bubbles, 2 % extreme words that reach the saturation
// paths) into the verilated TEM `Model` and compares every output with
// tem_edge<Fmt, kArms, kDamper>. With the damper, its coefficients are drawn over the
// ranges the host writes, and 2 % of the materials get any packed word for d_lo, d_span, zk,
// s_base and s_c2 (negative slopes, shifts far out of range: the clamps and flags of
// hls::damper_coefs). With hardening, likewise for hk, s_k and ct_h (hls::hardened_coefs).
template <class Model, int kArms, bool kDamper = false, bool kHardening = false>
void expect_rtl_tem_matches_bit_true() {
  constexpr int kDamperCoefs = kDamper ? 6 : 0;
  constexpr int kHardCoefs = kHardening ? 3 : 0;
  constexpr int kCoefs = 6 + kDamperCoefs + kHardCoefs + 2 * kArms;
  constexpr int kCoefWords = (kCoefs * 24 + 31) / 32;
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::int64_t> small_pos(0, std::int64_t(6) << Fmt::kFracX);
  std::uniform_int_distribution<std::int64_t> any_word(INT32_MIN, INT32_MAX);
  std::uniform_int_distribution<std::int64_t> small_p(-(1 << 20), 1 << 20);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto ctx = std::make_unique<VerilatedContext>();
  auto tem = std::make_unique<Model>(ctx.get());
  rtl_test::reset(*tem);
  std::deque<Expected> pending;
  int checked = 0, saturated = 0;
  for (int cycle = 0; cycle < kEdges + tem_latency(kHardening, kDamper); ++cycle) {
    tem->clk_i = 0;
    const bool issue = cycle < kEdges && unit(rng) < 0.9;  // some bubbles
    tem->valid_i = issue;
    if (issue) {
      const bool extreme = unit(rng) < 0.02;
      TemIn in;
      for (int a = 0; a < 3; ++a) {
        in.xs[a] = extreme ? any_word(rng) : small_pos(rng);
        in.xe[a] = extreme ? any_word(rng) : small_pos(rng);
        in.ps[a] = extreme ? any_word(rng) : small_p(rng);
        in.pe[a] = extreme ? any_word(rng) : small_p(rng);
      }
      in.L = small_pos(rng);
      in.d = extreme ? any_word(rng) : in.L + small_p(rng) * 64;
      MaterialCoefs mc;
      mc.alpha = driver::encode_coef(std::exp2(-20 * unit(rng)), "alpha", S::kAlpha);
      mc.beta = driver::encode_coef(unit(rng), "beta", S::kBeta);
      mc.kt = driver::encode_coef(unit(rng), "kt", S::kKt);
      mc.ct = driver::encode_coef(std::exp2(12 * unit(rng)), "ct", S::kCt);
      mc.a_min = driver::encode_coef(0.5 + 0.5 * unit(rng), "a_min", 0);
      mc.a_max = driver::encode_coef(1.0 + unit(rng), "a_max", 0);
      mc.flags = std::uint32_t(cycle & 3);
      if constexpr (kDamper) {
        if (unit(rng) < 0.02) {
          std::uniform_int_distribution<std::uint32_t> any_packed(0, (1u << 24) - 1);
          for (Coef* c : {&mc.d_lo, &mc.d_span, &mc.zk, &mc.s_base, &mc.s_c2})
            *c = rtl_test::unpack_coef(any_packed(rng));
        } else {
          mc.d_lo = driver::encode_coef(0.05 * unit(rng), "d_lo", 0);
          mc.d_span = driver::encode_coef(0.2 * unit(rng), "d_span", 0);
          // z up to ~12 over the span: c2 falls by up to 2^12
          mc.zk = driver::encode_coef(std::exp2(-8 - 8 * unit(rng)), "zk", 0);
          const double sb = std::exp2(-14 * unit(rng));
          mc.s_base = driver::encode_coef(sb, "s_base", 0);
          mc.s_c2 = driver::encode_coef(1.0 - sb, "s_c2", 0);
        }
        // ka is an ordinary coefficient (the host keeps its shift + extra >= 0)
        mc.ka = driver::encode_coef(kArms > 0 ? 2.0 * unit(rng) : 0.0, "ka", S::kCt);
      }
      if constexpr (kHardening) {
        if (unit(rng) < 0.02) {
          std::uniform_int_distribution<std::uint32_t> any_packed(0, (1u << 24) - 1);
          for (Coef* c : {&mc.hk, &mc.s_k, &mc.ct_h}) *c = rtl_test::unpack_coef(any_packed(rng));
        } else {
          mc.hk = driver::encode_coef(std::exp2(10 * unit(rng) - 5), "hk", 0);
          mc.s_k = driver::encode_coef(std::exp2(-14 * unit(rng)), "s_k", 0);
          mc.ct_h = driver::encode_coef(unit(rng), "ct_h", S::kCt);
        }
      }
      for (int j = 0; j < kArms; ++j) {
        in.m[j] = extreme ? any_word(rng) : small_p(rng) * 64;
        mc.gamma[j] = driver::encode_coef(std::exp2(-14 * unit(rng)), "gamma", S::kGamma);
        mc.k2t[j] = driver::encode_coef(2.0 * unit(rng), "k2t", S::kK2t);
        // m_i is one word with one arm, a word array ({arm K-1, ..., arm 0}) with more
        if constexpr (kArms == 1) tem->m_i = std::uint32_t(in.m[j]);
        else if constexpr (kArms > 1) tem->m_i[j] = std::uint32_t(in.m[j]);
      }
      for (int a = 0; a < 3; ++a) {
        tem->xs_i[a] = std::uint32_t(in.xs[a]);
        tem->xe_i[a] = std::uint32_t(in.xe[a]);
        tem->ps_i[a] = std::uint32_t(in.ps[a]);
        tem->pe_i[a] = std::uint32_t(in.pe[a]);
      }
      tem->d_i = std::uint32_t(in.d);
      tem->len_i = std::uint32_t(in.L);
      const Coef* coefs[15 + 2 * kMaxArms] = {&mc.alpha, &mc.beta, &mc.kt,
                                              &mc.ct,    &mc.a_min, &mc.a_max};
      if constexpr (kDamper) {
        const Coef* damper[6] = {&mc.d_lo, &mc.d_span, &mc.zk, &mc.s_base, &mc.s_c2, &mc.ka};
        for (int c = 0; c < 6; ++c) coefs[6 + c] = damper[c];
      }
      if constexpr (kHardening) {
        const Coef* hard[3] = {&mc.hk, &mc.s_k, &mc.ct_h};
        for (int c = 0; c < 3; ++c) coefs[6 + kDamperCoefs + c] = hard[c];
      }
      for (int j = 0; j < kMaxArms; ++j) {
        coefs[6 + kDamperCoefs + kHardCoefs + 2 * j] = &mc.gamma[j];
        coefs[7 + kDamperCoefs + kHardCoefs + 2 * j] = &mc.k2t[j];
      }
      // coef_i packs the 24-bit fields (six, the damper's six, two per arm) into 32-bit words.
      for (int w = 0; w < kCoefWords; ++w) tem->coef_i[w] = 0;
      for (int c = 0; c < kCoefs; ++c) {
        const std::uint64_t v = rtl_test::pack_coef(*coefs[c]);
        const int bit = c * 24;
        tem->coef_i[bit / 32] |= std::uint32_t(v << (bit % 32));
        if (bit % 32 > 8) tem->coef_i[bit / 32 + 1] |= std::uint32_t(v >> (32 - bit % 32));
      }
      tem->mat_flags_i = mc.flags;
      tem->idx_i = cycle & 0xFFFF;
      std::uint32_t status = 0;
      const TemOut out = tem_edge<Fmt, kArms, kDamper, kHardening>(in, mc, &status);
      pending.push_back({cycle & 0xFFFF, out, status});
    }
    tem->eval();
    tem->clk_i = 1;
    tem->eval();
    if (tem->valid_o) {
      ASSERT_FALSE(pending.empty());
      const Expected e = pending.front();
      pending.pop_front();
      ASSERT_EQ(int(tem->idx_o), e.idx);
      for (int a = 0; a < 3; ++a)
        ASSERT_EQ(std::int32_t(tem->f_o[a]), e.out.f[a]) << "edge " << e.idx << " f" << a;
      ASSERT_EQ(std::int32_t(tem->d_o), e.out.d) << "edge " << e.idx;
      for (int j = 0; j < kArms; ++j) {
        std::uint32_t m_word = 0;
        if constexpr (kArms == 1) m_word = tem->m_o;
        else if constexpr (kArms > 1) m_word = tem->m_o[j];
        ASSERT_EQ(std::int32_t(m_word), e.out.m[j]) << "edge " << e.idx << " arm " << j;
      }
      ASSERT_EQ(bool(tem->sat_o), bool(e.status & kStatusTemSaturated)) << "edge " << e.idx;
      ASSERT_EQ(bool(tem->degenerate_o), bool(e.status & kStatusDegenerateEdge));
      saturated += tem->sat_o;
      ++checked;
    }
  }
  tem->final();
  EXPECT_TRUE(pending.empty());
  EXPECT_GT(checked, kEdges * 8 / 10);
  EXPECT_GT(saturated, 0) << "the extreme inputs should reach the saturation paths";
}

TEST(RtlTem, MatchesTheBitTrueTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem, 0>();
}

TEST(RtlTemArm, MatchesTheBitTrueArmTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_arm, 1>();
}

TEST(RtlTemArms4, MatchesTheBitTrueFourArmTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_arms4, 4>();
}

TEST(RtlTemArms8, MatchesTheBitTrueEightArmTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_arms8, 8>();
}

TEST(RtlTemDamper, MatchesTheBitTrueDamperTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_damper, 0, true>();
}

TEST(RtlTemDamperArms8, MatchesTheBitTrueDamperAndEightArmTemWordForWordAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_damper_arms8, 8, true>();
}

TEST(RtlTemHardening, MatchesTheBitTrueHardeningTemWordForWordOnRandomInputsAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_hardening, 0, false, true>();
}

TEST(RtlTemEvery, MatchesTheBitTrueTemWithEveryEffectWordForWordAtOneEdgePerClock) {
  expect_rtl_tem_matches_bit_true<Vrheo_tem_every, 8, true, true>();
}

}  // namespace
}  // namespace rheo::hls
