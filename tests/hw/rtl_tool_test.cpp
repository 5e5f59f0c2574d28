// The RTL tool unit (rtl/rheo_tool.sv, verilated alone) against the bit-true tool_particle
// (hls/tool_contact.hpp) on random particles fed one per clock, for planes, spheres and
// cylinders in random poses, with and without friction (turning cylinders, particles of
// random inverse mass, some without a cap): every force word, the contact and saturation
// flags, the index and the valid timing must be equal. The tool's registers change between
// passes, as the core changes them between steps.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_tool.h"
#pragma GCC diagnostic pop

#include <cmath>
#include <deque>
#include <memory>
#include <random>

#include "hls/tool_contact.hpp"
#include "host/driver/core_image.hpp"
#include "tests/hw/rtl_harness.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
constexpr int kPasses = 120;
constexpr int kParticlesPerPass = 1500;
constexpr int kIdxMask = (1 << 12) - 1;  // IdxW = 12

struct Expected {
  int idx;
  int issue_cycle;
  ToolOut out;
  std::uint32_t status;
};

struct Coverage {
  int checked = 0, contact = 0, saturated = 0;
  int in_reach_pulling = 0;  // in reach but the damper pulls: no force
  int sliding = 0, stopped = 0;  // in contact with mu > 0: F_t = mu F_n, or the cap
  int contact_by_kind[4] = {};
};

class RtlToolTest : public ::testing::Test {
 protected:
  RtlToolTest() : tool_(std::make_unique<Vrheo_tool>(ctx_.get())) {
    rtl_test::reset(*tool_);
    tool_->clk_i = 0;
  }
  ~RtlToolTest() override { tool_->final(); }

  void clock() {
    tool_->eval();
    tool_->clk_i = 1;
    tool_->eval();
    ++cycle_;
    if (tool_->valid_o) check_output();
    tool_->clk_i = 0;
  }

  void check_output() {
    ASSERT_FALSE(pending_.empty()) << "valid_o without a particle in flight, cycle " << cycle_;
    const Expected e = pending_.front();
    pending_.pop_front();
    ASSERT_EQ(cycle_ - e.issue_cycle, kToolLatency) << "particle " << e.idx;
    ASSERT_EQ(int(tool_->idx_o), e.idx);
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(std::int32_t(tool_->f_o[a]), e.out.f[a]) << "particle " << e.idx << " f" << a;
    ASSERT_EQ(bool(tool_->contact_o), e.out.contact) << "particle " << e.idx;
    ASSERT_EQ(bool(tool_->sat_o), bool(e.status & kStatusMpmSaturated)) << "particle " << e.idx;
    ++cov_.checked;
    cov_.contact += e.out.contact;
    cov_.saturated += tool_->sat_o;
  }

  void set_regs(const ToolRegs& t) {
    tool_->kind_i = t.kind;
    for (int a = 0; a < 3; ++a) {
      tool_->c_i[a] = std::uint32_t(t.c[a]);
      tool_->dc_i[a] = std::uint32_t(t.dc[a]);
    }
    // a: three 18-bit operands packed into 54 bits
    const std::uint64_t mask = (std::uint64_t(1) << Fmt::kOperandBits) - 1;
    std::uint64_t packed = 0;
    for (int a = 0; a < 3; ++a)
      packed |= (std::uint64_t(t.a[a]) & mask) << (a * Fmt::kOperandBits);
    tool_->a_i = packed;
    tool_->reach_i = std::uint32_t(t.reach);
    tool_->half_len_i = std::uint32_t(t.half_length);
    tool_->kt_i = rtl_test::pack_coef(t.kt);
    tool_->ct_i = rtl_test::pack_coef(t.ct);
    tool_->mu_i = rtl_test::pack_coef(t.mu);
    tool_->spin_i = rtl_test::pack_coef(t.spin);
  }

  void issue(const std::int64_t* x, const std::int64_t* p, const Coef& minv, const ToolRegs& t) {
    tool_->valid_i = x != nullptr;
    if (x == nullptr) return;
    const int idx = cycle_ & kIdxMask;
    for (int a = 0; a < 3; ++a) {
      tool_->x_i[a] = std::uint32_t(x[a]);
      tool_->p_i[a] = std::uint32_t(p[a]);
    }
    tool_->idx_i = idx;
    tool_->minv_i = rtl_test::pack_coef(minv);
    Expected e{idx, cycle_, {}, 0};
    e.out = tool_particle<Fmt>(x, p, minv, t, &e.status);
    if (e.out.contact && t.mu.mant != 0) {
      // sliding if the force equals the one with a huge mass (no cap), else stopped
      std::uint32_t st = 0;
      const ToolOut free = tool_particle<Fmt>(x, p, Coef{0, 0}, t, &st);
      bool same = true;
      for (int a = 0; a < 3; ++a) same = same && free.f[a] == e.out.f[a];
      ++(same ? cov_.sliding : cov_.stopped);
    }
    if (!e.out.contact && e.status == 0) {
      // in reach with F_n <= 0 (the damper pulls): counted for coverage
      std::uint32_t st = 0;
      ToolRegs no_damper = t;
      no_damper.ct = Coef{0, 0};
      cov_.in_reach_pulling += tool_particle<Fmt>(x, p, minv, no_damper, &st).contact;
    }
    if (e.out.contact) ++cov_.contact_by_kind[t.kind];
    pending_.push_back(e);
  }

  void drain() {
    tool_->valid_i = 0;
    for (int k = 0; k < kToolLatency + 2; ++k) clock();
    ASSERT_TRUE(pending_.empty());
  }

  std::unique_ptr<VerilatedContext> ctx_ = std::make_unique<VerilatedContext>();
  std::unique_ptr<Vrheo_tool> tool_;
  std::deque<Expected> pending_;
  int cycle_ = 0;
  Coverage cov_;
};

TEST_F(RtlToolTest, MatchesTheBitTrueToolUnitWordForWordOnRandomParticlesAtOneParticlePerClock) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> any_word(INT32_MIN, INT32_MAX);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // X is Q5.27: positions within a few Lu, tools of 0.05..2 Lu, contact stiffness and
  // damping over several decades (as encode_tool makes them).
  const double lsb_x = std::ldexp(1.0, Fmt::kFracX);
  const double lsb_p = std::ldexp(1.0, Fmt::kFracP);
  for (int pass = 0; pass < kPasses; ++pass) {
    ToolRegs t;
    t.kind = pass % 4;  // off, plane, sphere, cylinder in turn
    const bool extreme = pass % 10 == 9;
    double axis[3] = {gauss(rng), gauss(rng), gauss(rng)};
    const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const double radius = 0.05 + 2.0 * unit(rng);
    const double centre[3] = {4 * unit(rng) - 2, 4 * unit(rng) - 2, 4 * unit(rng) - 2};
    for (int a = 0; a < 3; ++a) {
      t.c[a] = extreme ? any_word(rng) : std::llround(centre[a] * lsb_x);
      t.dc[a] = extreme ? any_word(rng) : std::llround(0.01 * gauss(rng) * lsb_p);
      t.a[a] = std::llround(std::ldexp(axis[a] / norm, Fmt::kFracU));
    }
    const double eps = 0.001 + 0.05 * unit(rng);
    t.reach = std::llround((t.kind == kToolPlane ? eps : radius + eps) * lsb_x);
    t.half_length = std::llround((0.1 + 3.0 * unit(rng)) * lsb_x);
    using S = CoefShifts<Fmt>;
    t.kt = driver::encode_coef(std::exp2(-4 + 14 * unit(rng)), "kt", S::kKt);
    t.ct = unit(rng) < 0.2 ? Coef{0, 0}
                           : driver::encode_coef(std::exp2(-6 + 14 * unit(rng)), "ct", S::kCt);
    // friction in four passes of five; a turning surface of up to ~0.03 Lu per step
    t.mu = pass % 5 == 0 ? Coef{0, 0} : driver::encode_coef(1.5 * unit(rng), "mu", S::kMu);
    t.spin = t.kind != kToolCylinder || unit(rng) < 0.3
                 ? Coef{0, 0}
                 : driver::encode_coef(0.01 * gauss(rng) * lsb_p, "spin", S::kSpin);
    if (extreme) t.spin = driver::encode_coef(any_word(rng) * 2.0, "spin", S::kSpin);
    set_regs(t);
    for (int n = 0; n < kParticlesPerPass; ++n) {
      if (unit(rng) < 0.05) {  // a few bubbles
        issue(nullptr, nullptr, Coef{}, t);
        clock();
        continue;
      }
      // Particles near the tool's surface (half of them within its reach), a few anywhere.
      std::int64_t x[3], p[3];
      const bool wild = extreme || unit(rng) < 0.02;
      double dir[3] = {gauss(rng), gauss(rng), gauss(rng)};
      const double dn = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
      const double dist = radius + (unit(rng) - 0.6) * 4 * eps;  // about the surface
      for (int a = 0; a < 3; ++a) {
        const double near = centre[a] + (t.kind == kToolPlane ? 0.3 * radius * dir[a] / dn
                                                               : dist * dir[a] / dn);
        x[a] = wild ? any_word(rng) : std::llround(near * lsb_x);
        p[a] = wild ? any_word(rng) : std::llround(0.005 * gauss(rng) * lsb_p);
      }
      if (t.kind == kToolPlane && !wild) {
        // set the signed distance along the normal to about the threshold
        double along = 0;
        for (int a = 0; a < 3; ++a) along += (x[a] / lsb_x - centre[a]) * axis[a] / norm;
        const double want = (unit(rng) - 0.6) * 4 * eps;
        for (int a = 0; a < 3; ++a) x[a] += std::llround((want - along) * axis[a] / norm * lsb_x);
      }
      // inverse masses over six decades, up to the format's 64 (the scenes' are near 1),
      // a few without a cap (minv <= 0: fixed particles' words)
      const double u_m = unit(rng);
      const Coef minv = u_m < 0.03   ? Coef{0, 0}
                        : u_m < 0.05 ? Coef{-5, 3}
                                     : driver::encode_coef(std::exp2(-14 + 19.5 * unit(rng)), "minv",
                                                           S::kMinv);
      issue(x, p, minv, t);
      clock();
    }
    drain();  // the registers hold while particles are in flight (the core's pass)
  }
  std::printf("checked %d particles: %d in contact (plane %d, sphere %d, cylinder %d; "
              "friction: %d sliding, %d stopped), %d saturated, %d pulled by the damper\n",
              cov_.checked, cov_.contact, cov_.contact_by_kind[kToolPlane],
              cov_.contact_by_kind[kToolSphere], cov_.contact_by_kind[kToolCylinder],
              cov_.sliding, cov_.stopped, cov_.saturated, cov_.in_reach_pulling);
  EXPECT_GT(cov_.contact_by_kind[kToolPlane], 1000);
  EXPECT_GT(cov_.contact_by_kind[kToolSphere], 1000);
  EXPECT_GT(cov_.contact_by_kind[kToolCylinder], 500);
  EXPECT_GT(cov_.saturated, 10);
  EXPECT_GT(cov_.in_reach_pulling, 100);
  EXPECT_GT(cov_.sliding, 1000);
  EXPECT_GT(cov_.stopped, 1000);
}

}  // namespace
}  // namespace rheo::hls
