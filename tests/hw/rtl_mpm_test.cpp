// The RTL MPM (rtl/rheo_mpm.sv, verilated alone) against the bit-true mpm_particle on
// random particles fed one per clock (hold while pushing on and off): every output word (x, p, plate force), the
// saturation flag, the index and the valid timing must be equal.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_mpm.h"
#pragma GCC diagnostic pop

#include <deque>
#include <memory>
#include <random>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "tests/hw/rtl_harness.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
constexpr int kPasses = 100;           // the globals change between passes
constexpr int kParticlesPerPass = 2000;
constexpr int kIdxMask = (1 << 12) - 1;  // IdxW = 12

struct Expected {
  int idx;
  int issue_cycle;
  MpmParticle out;
  std::int64_t plate_force;
  std::uint32_t status;
};

struct Coverage {
  int checked = 0, saturated = 0, held = 0, floored = 0, fixed = 0, left_shift = 0;
  int kept = 0;  // held in the previous step and pushing, with hold-while-pushing on
  // Plate particles on the plate before whose new displacement is within half an X LSB of
  // the plate's step (their rounded position lands on the plate): held when p.z > lim, and
  // free otherwise.
  int stayed = 0, left = 0;
  int rounds_out = 0;  // minv f rounds to exactly 2^31: the rounding leaves the word
  int rounds_to_min = 0;  // minv f rounds to exactly -2^31 from below: the word's end
};

// A coefficient and forces whose products minv f land within a few LSBs of +-2^31 after
// the shift: the edges of dp's saturation, 2^31 - 1/2 (rounds out of the word) included.
Coef word_edge_coef(std::int64_t f[3], std::mt19937_64& rng) {
  std::uniform_int_distribution<int> net_shift(1, 16);
  std::uniform_int_distribution<int> mant(1 << 16, (1 << 17) - 1);
  std::uniform_int_distribution<int> offset(-3, 3);
  const int s = net_shift(rng);
  const int m = mant(rng);
  for (int a = 0; a < 3; ++a) {
    // f m 2^-s = +-2^31 (+- a few half LSBs): f = +-2^(31 + s) / m, nudged.
    const std::int64_t edge = (std::int64_t(1) << (31 + s)) / m;
    f[a] = (a == 1 ? -edge : edge) + offset(rng);
  }
  return Coef{m, s - CoefShifts<Fmt>::kMinv};
}

class RtlMpmTest : public ::testing::Test {
 protected:
  RtlMpmTest() : mpm_(std::make_unique<Vrheo_mpm>(ctx_.get())) {
    rtl_test::reset(*mpm_);
    mpm_->clk_i = 0;
  }
  ~RtlMpmTest() override { mpm_->final(); }

  // One clock: inputs were set with the clock low; the module samples them on the edge.
  // Checks the output the edge produced against the oldest particle in flight.
  void clock() {
    mpm_->eval();
    mpm_->clk_i = 1;
    mpm_->eval();
    ++cycle_;
    if (mpm_->valid_o) check_output();
    mpm_->clk_i = 0;
  }

  void check_output() {
    ASSERT_FALSE(pending_.empty()) << "valid_o without a particle in flight, cycle " << cycle_;
    const Expected e = pending_.front();
    pending_.pop_front();
    ASSERT_EQ(cycle_ - e.issue_cycle, kMpmLatency) << "particle " << e.idx;
    ASSERT_EQ(int(mpm_->idx_o), e.idx);
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(std::int32_t(mpm_->x_o[a]), e.out.x[a]) << "particle " << e.idx << " x" << a;
      ASSERT_EQ(std::int32_t(mpm_->p_o[a]), e.out.p[a]) << "particle " << e.idx << " p" << a;
    }
    ASSERT_EQ(std::int32_t(mpm_->plate_f_o), e.plate_force) << "particle " << e.idx;
    ASSERT_EQ(bool(mpm_->sat_o), bool(e.status & kStatusMpmSaturated)) << "particle " << e.idx;
    ++cov_.checked;
    cov_.saturated += mpm_->sat_o;
  }

  void set_globals(const MpmGlobals& g) {
    for (int a = 0; a < 3; ++a) mpm_->g_i[a] = std::uint32_t(g.g[a]);
    mpm_->plate_z_i = std::uint32_t(g.plate_z);
    mpm_->plate_en_i = g.plate_enable;
    mpm_->floor_en_i = g.floor_enable;
    mpm_->hold_en_i = g.plate_hold && g.plate_prev_valid;
    mpm_->prev_valid_i = g.plate_prev_valid;
    mpm_->plate_prev_i = std::uint32_t(g.plate_z_prev);
  }

  // Presents one particle (computing what the bit-true MPM makes of it) or a bubble.
  void issue(const MpmParticle* q, const std::int64_t* f, const MpmGlobals& g) {
    mpm_->valid_i = q != nullptr;
    if (q == nullptr) return;
    const int idx = cycle_ & kIdxMask;
    for (int a = 0; a < 3; ++a) {
      mpm_->f_i[a] = std::uint32_t(f[a]);
      mpm_->x_i[a] = std::uint32_t(q->x[a]);
      mpm_->p_i[a] = std::uint32_t(q->p[a]);
      mpm_->x0_i[a] = std::uint32_t(q->x0[a]);
    }
    mpm_->minv_i = rtl_test::pack_coef(q->minv);
    mpm_->flags_i = q->flags;
    mpm_->idx_i = idx;
    Expected e{idx, cycle_, *q, 0, 0};
    e.plate_force = mpm_particle<Fmt>(e.out, f, g, &e.status);
    pending_.push_back(e);
  }

  std::unique_ptr<VerilatedContext> ctx_ = std::make_unique<VerilatedContext>();
  std::unique_ptr<Vrheo_mpm> mpm_;
  std::deque<Expected> pending_;
  int cycle_ = 0;
  Coverage cov_;
};

TEST_F(RtlMpmTest, MatchesTheBitTrueMpmWordForWordOnRandomParticlesAtOneParticlePerClock) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> any_word(INT32_MIN, INT32_MAX);
  // Positions up to 4 Lu either side of 0 (X: Q5.27), so the floor and the plate
  // (placed in the same range) are crossed often.
  std::uniform_int_distribution<std::int64_t> pos(-(std::int64_t(1) << 29),
                                                   std::int64_t(4) << 27);
  std::uniform_int_distribution<std::int64_t> small_p(-(1 << 26), 1 << 26);
  std::uniform_int_distribution<std::int64_t> force(-(1 << 22), 1 << 22);  // 4 Fu
  std::uniform_int_distribution<int> mant(-(1 << 17), (1 << 17) - 1);
  std::uniform_int_distribution<int> shift(-kCoefShiftBias,
                                           (1 << kCoefShiftBits) - 1 - kCoefShiftBias);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto word = [&](bool extreme, std::int64_t ordinary) {
    return extreme ? any_word(rng) : ordinary;
  };
  for (int pass = 0; pass < kPasses; ++pass) {
    MpmGlobals g;
    const bool extreme_g = unit(rng) < 0.1;
    std::uniform_int_distribution<std::int64_t> gravity(-(1 << 12), 1 << 12);
    for (int a = 0; a < 3; ++a) g.g[a] = word(extreme_g, gravity(rng));
    const bool extreme_z = unit(rng) < 0.1;  // drawn first, as under every compiler
    g.plate_z = word(extreme_z, pos(rng));
    g.plate_enable = unit(rng) < 0.7;
    g.floor_enable = unit(rng) < 0.7;
    g.plate_hold = unit(rng) < 0.5;
    g.plate_prev_valid = unit(rng) < 0.8;
    const bool extreme_z_prev = unit(rng) < 0.1;
    g.plate_z_prev = word(extreme_z_prev, pos(rng));
    set_globals(g);
    for (int n = 0; n < kParticlesPerPass; ++n) {
      if (unit(rng) < 0.05) {  // a few bubbles
        issue(nullptr, nullptr, g);
        clock();
        continue;
      }
      // Mostly realistic particles; 3 % extreme words to reach every saturation.
      const bool extreme = unit(rng) < 0.03;
      MpmParticle q;
      std::int64_t f[3];
      for (int a = 0; a < 3; ++a) {
        q.x[a] = word(extreme, pos(rng));
        q.p[a] = word(extreme, small_p(rng));
        q.x0[a] = word(extreme, pos(rng));
        f[a] = word(extreme, force(rng));
      }
      // minv as the host encodes it (mass scaling over many decades), or any coefficient
      // word at all: shifts below -kMinv make the product shift left.
      const double coef_kind = unit(rng);
      if (coef_kind < 0.75) {
        q.minv = driver::encode_coef(std::exp2(-2 - 22 * unit(rng)), "minv",
                                     CoefShifts<Fmt>::kMinv);
      } else if (coef_kind < 0.95) {
        q.minv = Coef{mant(rng), shift(rng)};
        cov_.left_shift += q.minv.shift + CoefShifts<Fmt>::kMinv < 0;
      } else {
        q.minv = word_edge_coef(f, rng);
      }
      for (int a = 0; a < 3; ++a) {
        const int s = q.minv.shift + CoefShifts<Fmt>::kMinv;
        const i128 prod = i128(f[a]) * q.minv.mant;
        const i128 dp = shift_round<Fmt::kRounding>(prod, s);
        cov_.rounds_out += dp == i128(1) << 31;
        cov_.rounds_to_min += dp == -(i128(1) << 31) && s > 0 && prod < dp << s;
      }
      // A third of the particles sit at the previous plate height (held in the previous
      // step, if they are plate particles).
      if (unit(rng) < 0.3) q.x[2] = g.plate_z_prev;
      // A sixth sat on the plate (at the previous plate height) and move within half an X
      // LSB of the plate's step: p.z + minv f.z + g.z = lim + delta, |delta| < 8, so their
      // rounded position lands on the plate. They stay on it when delta > 0 (p.z > lim, as
      // the reference's v > V_plate) and leave it otherwise.
      int delta = 0;
      bool near_step = false;
      if (!extreme && unit(rng) < 1.0 / 6.0) {
        const int s = q.minv.shift + CoefShifts<Fmt>::kMinv;
        const i128 dp = shift_round<Fmt::kRounding>(i128(f[2]) * q.minv.mant, s);
        const i128 lim = (i128(g.plate_z) - g.plate_z_prev) << (Fmt::kFracP - Fmt::kFracX);
        delta = std::uniform_int_distribution<int>(-7, 7)(rng);
        const i128 p = lim + delta - dp - g.g[2];
        const auto fits = [](i128 v) { return v >= INT32_MIN && v <= INT32_MAX; };
        if (fits(lim) && fits(p) && fits(i128(p) + dp) && fits(dp)) {
          q.x[2] = g.plate_z_prev;
          q.p[2] = std::int64_t(p);
          near_step = true;
        }
      }
      const double kind = unit(rng);
      q.flags = kind < 0.15 ? kCoreFixed
                : kind < 0.5 ? kCorePlate
                : kind < 0.55 ? kCoreFixed | kCorePlate
                              : 0;
      issue(&q, f, g);
      const Expected& e = pending_.back();
      cov_.fixed += (q.flags & kCoreFixed) != 0;
      cov_.held += e.plate_force != 0;
      cov_.kept += q.flags == kCorePlate && g.plate_enable && g.plate_hold &&
                   g.plate_prev_valid && q.x[2] == g.plate_z_prev && f[2] > 0 &&
                   e.out.x[2] == g.plate_z;
      cov_.floored += !(q.flags & kCoreFixed) && g.floor_enable && e.out.x[2] == 0;
      const bool near = near_step && q.flags == kCorePlate && g.plate_enable &&
                        g.plate_prev_valid && f[2] != 0 && e.out.x[2] == g.plate_z;
      cov_.stayed += near && delta > 0 && e.plate_force == f[2];
      cov_.left += near && delta <= 0 && !(g.plate_hold && f[2] > 0) && e.plate_force == 0;
      clock();
      if (HasFatalFailure()) return;
    }
    // Drain before the globals change: the module reads them at the stage using them.
    mpm_->valid_i = 0;
    for (int k = 0; k < kMpmLatency; ++k) {
      clock();
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_TRUE(pending_.empty());
  EXPECT_GT(cov_.checked, kPasses * kParticlesPerPass * 9 / 10);
  EXPECT_GT(cov_.saturated, 0) << "the extreme words should reach the saturation paths";
  EXPECT_GT(cov_.held, 1000) << "plate particles above an enabled plate";
  EXPECT_GT(cov_.kept, 1000) << "plate particles kept because they push (hold while pushing)";
  EXPECT_GT(cov_.floored, 1000) << "free particles below an enabled floor";
  EXPECT_GT(cov_.stayed, 300) << "on the plate before, moving faster than it by < 1/2 X LSB";
  EXPECT_GT(cov_.left, 300) << "on the plate before, not faster than it";
  EXPECT_GT(cov_.fixed, 1000);
  EXPECT_GT(cov_.left_shift, 100) << "coefficient words whose product shifts left";
  EXPECT_GT(cov_.rounds_out, 10) << "products whose rounding carries out of the word";
  EXPECT_GT(cov_.rounds_to_min, 10) << "products just below -2^31 that round up to it";
}

}  // namespace
}  // namespace rheo::hls
