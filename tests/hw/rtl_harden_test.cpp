// The RTL strain-hardening unit (rtl/rheo_harden.sv, verilated alone) against the bit-true
// hls::hardened_coefs<Fmt, Damper> on random inputs fed one per clock: every packed
// coefficient and the saturation flag must be equal. Built without the damper (Vrheo_harden)
// and with it (SeriesDamper = 1: Vrheo_harden_damper, whose damper follows the hardened
// spring's extension g |d - L|). The inputs are drawn over the ranges the host writes
// (driver::encode_hardening, driver::encode_damper) and, for 3 % of them, over any word
// (L <= 0, strains whose h leaves its word, any d - L, any packed hk, s_k, ct_h and damper
// coefficient), which reaches the clamps.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_harden.h"
#include "Vrheo_harden_damper.h"
#pragma GCC diagnostic pop

#include <cmath>
#include <deque>
#include <random>
#include <vector>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "tests/hw/rtl_harness.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
using S = CoefShifts<Fmt>;
constexpr int kCases = 40000;
constexpr int kLengthLead = 4;  // l_i's stage
// coef_o's stage: rheo_harden's latency, the TEM's extra latency plus 12 (rtl/rheo_tem.sv)
constexpr int latency(bool damper) { return (damper ? kHardDamperTemExtra : kHardTemExtra) + 12; }

// Packs 24-bit fields into the 32-bit words of a wide Verilator port.
template <std::size_t N>
void pack_fields(std::uint32_t (&words)[N], const Coef* const* coefs, int count) {
  for (std::size_t w = 0; w < N; ++w) words[w] = 0;
  for (int c = 0; c < count; ++c) {
    const std::uint64_t v = rtl_test::pack_coef(*coefs[c]);
    const int bit = c * 24;
    words[bit / 32] |= std::uint32_t(v << (bit % 32));
    if (bit % 32 > 8) words[bit / 32 + 1] |= std::uint32_t(v >> (32 - bit % 32));
  }
}

std::uint32_t field(const VlWide<4>& words, int c) {
  const int bit = c * 24;
  std::uint64_t v = words[bit / 32] >> (bit % 32);
  if (bit % 32 > 8) v |= std::uint64_t(words[bit / 32 + 1]) << (32 - bit % 32);
  return std::uint32_t(v & 0xFFFFFF);
}

struct Case {
  std::int64_t L = 0, l = 0, ds = 0;
  MaterialCoefs mc;
};

// A material as the host encodes it (test units: k1 = 1, Lu = 1 m, Fu = 1 N); one the host
// refuses (kt's limit c2 / dt beyond its format) is drawn again.
MaterialCoefs draw_material(std::mt19937_64& rng, bool damper) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (;;) {
    EdgeMaterial m;
    m.k1 = 1.0;
    const double dt = std::exp2(-12 * unit(rng));
    m.c1 = std::exp2(8 * unit(rng) - 4);
    m.c2 = std::exp2(8 * unit(rng) - 2);
    m.hardening = std::exp2(14 * unit(rng) - 7);
    if (damper) {  // c2 falls by up to 1000x between spring forces f1 and f2
      m.nonlinear = true;
      m.f1 = 0.5 * unit(rng);
      m.f2 = m.f1 + std::exp2(-6 + 6 * unit(rng));
      m.c2_min = m.c2 / std::exp2(10 * unit(rng));
    }
    const double c = m.c1 + m.c2 + m.k1 * dt;
    MaterialCoefs mc;
    try {
      mc.alpha = driver::encode_coef(m.k1 * dt / c, "alpha", S::kAlpha);
      mc.beta = driver::encode_coef(m.c2 / c, "beta", S::kBeta);
      mc.kt = driver::encode_coef(m.k1 * m.c2 / c, "kt", S::kKt);
      mc.ct = driver::encode_coef(m.c2 * (m.c1 + m.k1 * dt) / (c * dt), "ct", S::kCt);
      driver::encode_hardening(m, dt, 1.0, 1.0, "material 0: ", mc);
      if (damper) driver::encode_damper(m, dt, 1.0, 15.0, "material 0: ", mc);
      return mc;
    } catch (const Error&) {
    }
  }
}

Case draw(std::mt19937_64& rng, bool damper) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<std::int64_t> any_word(INT32_MIN, INT32_MAX);
  std::uniform_int_distribution<std::uint32_t> any_packed(0, (1u << 24) - 1);
  Case k;
  const bool extreme = unit(rng) < 0.03;
  k.mc = draw_material(rng, damper);
  // l within the X word's range (|l| < 16 units), as the TEM's l always is
  const double len = 0.05 + 4.0 * unit(rng);
  // 5 % unstrained (h = 0, cth = 0), the others from -0.9 to 2.1
  const double strain = unit(rng) < 0.05 ? 0.0 : 3.0 * unit(rng) - 0.9;
  k.L = std::llround(std::ldexp(len, Fmt::kFracX));
  k.l = std::llround(std::ldexp(len * (1.0 + strain), Fmt::kFracX));
  // the Voigt spring's extension d - L, up to the edge's own length either way
  const double ext = (2.0 * unit(rng) - 1.0) * len;
  k.ds = damper ? std::llround(std::ldexp(ext, Fmt::kFracX)) : 0;
  if (extreme) {
    const double what = unit(rng);
    if (what < 0.4) {
      k.L = any_word(rng);
      k.l = any_word(rng);
    } else if (damper && what < 0.55) {
      k.ds = any_word(rng);
    } else if (damper && what < 0.7) {
      for (Coef* cf : {&k.mc.d_lo, &k.mc.d_span, &k.mc.zk, &k.mc.s_base, &k.mc.s_c2})
        *cf = rtl_test::unpack_coef(any_packed(rng));
    } else {
      for (Coef* cf : {&k.mc.hk, &k.mc.s_k, &k.mc.ct_h, &k.mc.alpha, &k.mc.kt})
        *cf = rtl_test::unpack_coef(any_packed(rng));
    }
  }
  return k;
}

template <class Model, bool kDamper>
void expect_rtl_harden_matches_bit_true() {
  constexpr int kLatency = latency(kDamper);
  constexpr int kIn = kDamper ? 12 : 7;
  std::mt19937_64 rng(kDamper ? 79 : 73);
  auto ctx = std::make_unique<VerilatedContext>();
  auto unit = std::make_unique<Model>(ctx.get());
  std::deque<Case> issued;  // by cycle
  std::vector<Case> all;    // every case, for the report of a mismatch
  std::deque<std::pair<DampedCoefs, std::uint32_t>> expected;
  int checked = 0, flagged = 0, zero_cth = 0, damped = 0;
  for (int cycle = 0; cycle < kCases + kLatency + 1; ++cycle) {
    unit->clk_i = 0;
    if (cycle < kCases) {
      const Case k = draw(rng, kDamper);
      unit->len_i = std::uint32_t(k.L);
      unit->ds_i = std::uint32_t(k.ds);
      const Coef* coefs[12] = {&k.mc.alpha, &k.mc.beta, &k.mc.kt,     &k.mc.ct,
                               &k.mc.hk,    &k.mc.s_k,  &k.mc.ct_h,   &k.mc.d_lo,
                               &k.mc.d_span, &k.mc.zk,  &k.mc.s_base, &k.mc.s_c2};
      std::uint32_t words[(kIn * 24 + 31) / 32];
      pack_fields(words, coefs, kIn);
      for (int w = 0; w < (kIn * 24 + 31) / 32; ++w) unit->coef_i[w] = words[w];
      std::uint32_t status = 0;
      const DampedCoefs dc = hardened_coefs<Fmt, kDamper>(k.ds, k.l, k.L, k.mc, &status);
      if constexpr (kDamper) {  // the damper is past f1 (c2 below c2_max) in this case
        std::uint32_t ignored = 0;
        const DampedCoefs undamped = hardened_coefs<Fmt, false>(0, k.l, k.L, k.mc, &ignored);
        damped += dc.beta.mant != undamped.beta.mant || dc.beta.shift != undamped.beta.shift;
      }
      expected.emplace_back(dc, status);
      issued.push_back(k);
      all.push_back(k);
    }
    // l of the case issued kLengthLead clocks ago
    if (cycle >= kLengthLead && cycle - kLengthLead < kCases) {
      unit->l_i = std::uint32_t(issued.front().l);
      issued.pop_front();
    }
    unit->eval();
    unit->clk_i = 1;
    unit->eval();
    // after this edge, stage kLatency holds the case issued kLatency - 1 clocks ago
    if (cycle >= kLatency - 1 && !expected.empty()) {
      const auto [dc, status] = expected.front();
      expected.pop_front();
      const int n = cycle - (kLatency - 1);
      const Coef* want[5] = {&dc.alpha, &dc.beta, &dc.kt, &dc.ct, &dc.cth};
      const char* names[5] = {"alpha", "beta", "kt", "ct", "cth"};
      for (int c = 0; c < 5; ++c) {
        EXPECT_EQ(field(unit->coef_o, c), rtl_test::pack_coef(*want[c]) & 0xFFFFFF)
            << names[c] << ", case " << n;
      }
      ASSERT_EQ(bool(unit->clip_o), bool(status & kStatusTemSaturated)) << "case " << n;
      if (::testing::Test::HasFailure()) {  // the case's inputs, then stop
        const Case& k = all[n];
        std::printf("case %d: L %lld, l %lld, ds %lld, hk %d 2^-%d, s_k %d 2^-%d, ct_h %d 2^-%d\n",
                    n, static_cast<long long>(k.L), static_cast<long long>(k.l),
                    static_cast<long long>(k.ds), k.mc.hk.mant, k.mc.hk.shift, k.mc.s_k.mant,
                    k.mc.s_k.shift, k.mc.ct_h.mant, k.mc.ct_h.shift);
        return;
      }
      flagged += unit->clip_o;
      zero_cth += dc.cth.mant == 0;
      ++checked;
    }
  }
  unit->final();
  EXPECT_EQ(checked, kCases);
  EXPECT_GT(flagged, 100) << "the extreme inputs should reach the clamps";
  EXPECT_LT(flagged, kCases / 20) << "inputs the host writes should not be flagged";
  EXPECT_GT(zero_cth, 0) << "l = L (h = 0) should give cth = 0";
  if (kDamper) {
    EXPECT_GT(damped, kCases / 4) << "the damper should act in many cases";
  }
  std::printf("rheo_harden%s: %d cases equal, %d flagged, %d with cth = 0, %d damped\n",
              kDamper ? " with the damper" : "", checked, flagged, zero_cth, damped);
}

TEST(RtlHarden, MatchesTheBitTrueHardeningWordForWordOnRandomInputsAtOnePerClock) {
  expect_rtl_harden_matches_bit_true<Vrheo_harden, false>();
}

TEST(RtlHardenDamper, MatchesTheBitTrueHardenedDamperWordForWordOnRandomInputsAtOnePerClock) {
  expect_rtl_harden_matches_bit_true<Vrheo_harden_damper, true>();
}

}  // namespace
}  // namespace rheo::hls
